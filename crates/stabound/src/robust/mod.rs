//! Walls that hold for a set of devices, not one (the model document, docs/MODEL.md,
//! section 12).
//!
//! A [`DeviceSet`] is a device in physical units whose parameters may each be an interval
//! `lo..hi` or a finite list of values (mass, damping, delay, every element parameter), and,
//! when a hand is named, the same device with the hand let go. Its robust stable region is
//! the intersection of its members' stable regions; [`robust_alpha_max`] finds the largest
//! stiffness for which one damping is stable for every member, and [`robust_check`] says
//! whether one wall is.
//!
//! Walls are compared in one normalization for the whole set: the set's *reference* device
//! (every interval at its low end, every list at its smallest value), `alpha = K T^2 / m_ref`,
//! `beta = B T / m_ref`. A member of mass `m` sees the same physical wall as
//! `(m_ref / m) (alpha, beta)` in its own normalization. The sampling period is one value for
//! the whole set (firmware sets it).
//!
//! ```
//! use stabound::elements::PhysicalElements;
//! use stabound::params::{Delay, Device};
//! use stabound::robust::{DeviceSet, Quantity, robust_alpha_max};
//! use stabound::AmaxOptions;
//!
//! // the paper's device (normalized units: m = 1, T = 1), delay jittering between 1 and 2 samples
//! let device = Device::new(1.0, 1.0, 0.5, Delay::Samples(1.0))?;
//! let set = DeviceSet::new(&device, &PhysicalElements::default())?
//!     .with_interval(Quantity::Delay, 1.0, 2.0)?;
//! let r = robust_alpha_max(&set, &AmaxOptions::default())?;
//! // a longer delay lowers the stiffness: the robust wall is below the 1-sample one
//! let one = stabound::alpha_max(&device.plant()?, &AmaxOptions::default())?;
//! assert!(r.alpha_max < one.alpha_max && r.alpha_verified <= r.alpha_max);
//! # Ok::<(), stabound::Error>(())
//! ```

mod proof;
mod proof_elements;
mod region;
mod sample;
mod search;

pub use proof::{PROOF_BUDGET, Proof, ProofCell, prove_wall};
pub use region::{RobustRegion, robust_region};
pub use search::{RobustAmax, RobustCheck, Verification, robust_alpha_max, robust_check};

use crate::elements::list::{self, Accepts, Value};
use crate::elements::{Loop, PhysicalElements};
use crate::error::{Error, Result};
use crate::params::{Delay, Device, finite};
use crate::search::Interval;

/// The most parameters one set may spread over intervals: the search starts from every
/// corner of the box (`2^6 = 64`), and the sampling argument's cells have `2^k` corners.
pub const MAX_INTERVALS: usize = 6;

/// The most combinations of listed values (times hand on and off) one set may have: each is
/// searched and verified as a box of its own.
pub const MAX_VARIANTS: usize = 64;

/// A physical parameter of a device, or of its loop elements, that a [`DeviceSet`] may
/// spread: the device's mass, damping or delay, or a number-valued parameter of the element
/// list ([`crate::elements::list::PARAMS`]).
#[derive(Debug, Clone, Copy)]
#[non_exhaustive]
pub enum Quantity {
    /// Device mass `m`, kg.
    Mass,
    /// Physical damping `b`, N s/m.
    Damping,
    /// Delay, in the unit the device gives it (seconds or samples).
    Delay,
    /// A number-valued element parameter of the list.
    Element(&'static list::Param),
}

impl PartialEq for Quantity {
    fn eq(&self, other: &Self) -> bool {
        self.rank() == other.rank()
    }
}

impl Eq for Quantity {}

impl Quantity {
    /// The element parameter with Python keyword `keyword` (`hand_mass`), when it takes a
    /// number (a count or a choice spreads over no interval).
    ///
    /// # Errors
    ///
    /// An unknown keyword, or a parameter that takes no number.
    pub fn element(keyword: &str) -> Result<Self> {
        let p = list::param(keyword).ok_or_else(|| {
            Error::InvalidRequest(format!("no loop element parameter is called '{keyword}'"))
        })?;
        match p.accepts {
            Accepts::NonNegative | Accepts::Positive => Ok(Quantity::Element(p)),
            _ => Err(Error::InvalidRequest(format!(
                "the {} takes {}, not a range of numbers: give one value",
                p.name,
                p.expects()
            ))),
        }
    }

    /// The parameter's name as reports print it.
    pub fn name(self) -> &'static str {
        match self {
            Quantity::Mass => "mass",
            Quantity::Damping => "damping",
            Quantity::Delay => "delay",
            Quantity::Element(p) => p.name,
        }
    }

    /// The order sets keep their parameters in: the device's, then the list's.
    fn rank(self) -> usize {
        match self {
            Quantity::Mass => 0,
            Quantity::Damping => 1,
            Quantity::Delay => 2,
            Quantity::Element(p) => {
                3 + list::PARAMS
                    .iter()
                    .position(|q| q.key == p.key)
                    .unwrap_or(list::PARAMS.len())
            }
        }
    }

    /// The parameter's unit (`delay_in_seconds`: how the device gives its delay).
    fn unit(self, delay_in_seconds: bool) -> &'static str {
        match self {
            Quantity::Mass => "kg",
            Quantity::Damping => "N s/m",
            Quantity::Delay if delay_in_seconds => "s",
            Quantity::Delay => "samples",
            Quantity::Element(p) => p.unit,
        }
    }

    fn is_hand(self) -> bool {
        matches!(self, Quantity::Element(p) if p.element == list::Element::Hand)
    }

    fn set(self, device: &mut Device, e: &mut PhysicalElements, v: f64) {
        match self {
            Quantity::Mass => device.mass = v,
            Quantity::Damping => device.damping = v,
            Quantity::Delay => {
                device.delay = match device.delay {
                    Delay::Seconds(_) => Delay::Seconds(v),
                    Delay::Samples(_) => Delay::Samples(v),
                }
            }
            Quantity::Element(p) => p.set(e, Value::Number(v)),
        }
    }

    fn get(self, device: &Device, e: &PhysicalElements) -> Option<f64> {
        match self {
            Quantity::Mass => Some(device.mass),
            Quantity::Damping => Some(device.damping),
            Quantity::Delay => Some(match device.delay {
                Delay::Seconds(s) | Delay::Samples(s) => s,
            }),
            Quantity::Element(p) => match p.get(e) {
                Some(Value::Number(x)) => Some(x),
                _ => None,
            },
        }
    }
}

/// How one parameter spreads over a set of devices: every value of an interval, or each
/// value of a finite list ([`DeviceSet::with_spread`]).
///
/// ```
/// use stabound::robust::Spread;
///
/// // a delay that is 1, 2 or 3 samples, never in between
/// let delays = Spread::Values(vec![3.0, 1.0, 2.0]);
/// assert_eq!(delays.low(), 1.0);
/// assert_eq!(Spread::Interval(0.2, 0.5).low(), 0.2);
/// ```
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Spread {
    /// Every value in `[lo, hi]` (`lo < hi` once in a set; equal ends are one value).
    Interval(f64, f64),
    /// Each of these values (in a set: sorted, distinct; one value is that value alone).
    Values(Vec<f64>),
}

impl Spread {
    /// The smallest value: the set's reference member takes it (module documentation).
    /// A list's smallest finite value (`NaN` for an empty list, which a set refuses).
    pub fn low(&self) -> f64 {
        match self {
            Spread::Interval(lo, _) => *lo,
            Spread::Values(v) => v.iter().copied().fold(f64::NAN, f64::min),
        }
    }
}

/// A set of devices: one device in physical units with some parameters spread over intervals
/// or lists, and the device with its hand let go (module documentation).
///
/// Built with [`DeviceSet::new`] and the `with_` methods; every member is a valid loop
/// (checked at every corner of every box when the set is built).
#[derive(Debug, Clone, PartialEq)]
pub struct DeviceSet {
    device: Device,
    elements: PhysicalElements,
    spreads: Vec<(Quantity, Spread)>,
    may_let_go: bool,
}

/// One device of a [`DeviceSet`]: a device in physical units and the loop elements it has.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Member {
    device: Device,
    elements: PhysicalElements,
}

impl Member {
    /// The device.
    pub fn device(&self) -> &Device {
        &self.device
    }

    /// The loop elements named (the hand absent for the device let go).
    pub fn elements(&self) -> &PhysicalElements {
        &self.elements
    }

    /// Whether the operator's hand holds the handle in this member.
    pub fn hand_held(&self) -> bool {
        hand_params().any(|p| p.get(&self.elements).is_some())
    }

    /// The member's loop ([`Loop::physical`]).
    pub fn to_loop(&self) -> Result<Loop> {
        Loop::physical(&self.device, &self.elements)
    }
}

/// One box of a set: the listed values and hand state fixed, the intervals free.
#[derive(Debug, Clone)]
pub(crate) struct Variant {
    /// The member at the box's low corner (every interval at its low end).
    base: Member,
    /// The free parameters and their intervals.
    dims: Vec<(Quantity, f64, f64)>,
}

impl Variant {
    pub(crate) fn dims(&self) -> usize {
        self.dims.len()
    }

    /// The member at `coords` in `[0, 1]^k` (`lo + t (hi - lo)` per interval).
    pub(crate) fn member(&self, coords: &[f64]) -> Member {
        let mut m = self.base;
        for (&(p, lo, hi), &t) in self.dims.iter().zip(coords) {
            // the ends exactly, so corners are the values given
            let v = if t >= 1.0 { hi } else { lo + t * (hi - lo) };
            p.set(&mut m.device, &mut m.elements, v);
        }
        m
    }

    /// The `2^k` corners of the box.
    pub(crate) fn corners(&self) -> Vec<Vec<f64>> {
        let k = self.dims.len();
        (0..1usize << k)
            .map(|c| (0..k).map(|i| ((c >> i) & 1) as f64).collect())
            .collect()
    }
}

impl DeviceSet {
    /// The set holding `device` with the elements `named` and, when a hand is named, the
    /// device with the hand let go ([`DeviceSet::always_gripped`] removes it).
    ///
    /// # Errors
    ///
    /// As [`Loop::physical`].
    pub fn new(device: &Device, named: &PhysicalElements) -> Result<Self> {
        Loop::physical(device, named)?;
        let set = Self {
            device: *device,
            elements: *named,
            spreads: Vec::new(),
            may_let_go: false,
        };
        let held = set.reference().hand_held();
        Ok(Self {
            may_let_go: held,
            ..set
        })
    }

    /// The same set with `param` spread over `[lo, hi]` (`lo == hi`: that one value). An
    /// element parameter not named yet adds the element (its other parameters as named).
    ///
    /// # Errors
    ///
    /// A bound not finite, `lo > hi`, more than [`MAX_INTERVALS`] intervals, or a member
    /// that is no valid loop (checked at every corner).
    pub fn with_interval(self, param: Quantity, lo: f64, hi: f64) -> Result<Self> {
        finite(param.name(), lo)?;
        finite(param.name(), hi)?;
        if lo > hi {
            return Err(Error::InvalidRequest(format!(
                "the {} interval {lo}..{hi} is inverted: give the low end first",
                param.name()
            )));
        }
        // exact: equal ends are one value
        let spread = if lo == hi {
            Spread::Values(vec![lo])
        } else {
            Spread::Interval(lo, hi)
        };
        self.spread(param, spread)
    }

    /// The same set with `param` taking each of `values` (a finite set, e.g. the delays a
    /// product ships with).
    ///
    /// # Errors
    ///
    /// An empty list, a value not finite, more than [`MAX_VARIANTS`] combinations, or a
    /// member that is no valid loop.
    pub fn with_values(self, param: Quantity, values: &[f64]) -> Result<Self> {
        for &v in values {
            finite(param.name(), v)?;
        }
        let mut v = values.to_vec();
        v.sort_by(f64::total_cmp);
        v.dedup();
        if v.is_empty() {
            return Err(Error::InvalidRequest(format!(
                "the {} list is empty; give at least one value",
                param.name()
            )));
        }
        self.spread(param, Spread::Values(v))
    }

    /// The same set with `param` spread as `spread`: [`DeviceSet::with_interval`] for an
    /// interval, [`DeviceSet::with_values`] for a list (each checked as those are).
    ///
    /// ```
    /// use stabound::elements::PhysicalElements;
    /// use stabound::robust::{DeviceSet, Quantity, Spread};
    /// use stabound::{Delay, Device};
    ///
    /// let dev = Device::new(0.1, 1e-3, 1.0, Delay::Samples(1.0))?;
    /// let set = DeviceSet::new(&dev, &PhysicalElements::default())?
    ///     .with_spread(Quantity::Delay, &Spread::Values(vec![1.0, 2.0, 3.0]))?;
    /// assert!(!set.has_intervals() && !set.is_single());
    /// assert_eq!(set.describe(), ["delay 1 or 2 or 3 samples"]);
    /// # Ok::<(), stabound::Error>(())
    /// ```
    ///
    /// # Errors
    ///
    /// As [`DeviceSet::with_interval`] and [`DeviceSet::with_values`].
    pub fn with_spread(self, param: Quantity, spread: &Spread) -> Result<Self> {
        match spread {
            &Spread::Interval(lo, hi) => self.with_interval(param, lo, hi),
            Spread::Values(v) => self.with_values(param, v),
        }
    }

    fn spread(mut self, param: Quantity, spread: Spread) -> Result<Self> {
        self.spreads.retain(|(p, _)| *p != param);
        match spread {
            Spread::Values(v) if v.len() == 1 => {
                param.set(&mut self.device, &mut self.elements, v[0]);
            }
            s => {
                let low = match &s {
                    Spread::Interval(lo, _) => *lo,
                    Spread::Values(v) => v[0],
                };
                param.set(&mut self.device, &mut self.elements, low);
                self.spreads.push((param, s));
                self.spreads.sort_by_key(|(p, _)| p.rank());
            }
        }
        if param.is_hand() {
            self.may_let_go = self.may_let_go || self.reference().hand_held();
        }
        self.validated()
    }

    /// The same set with the hand always on the handle (`true`: the device let go is not a
    /// member) or able to let go (`false`, the default whenever a hand is named).
    pub fn always_gripped(mut self, gripped: bool) -> Self {
        self.may_let_go = !gripped && self.reference().hand_held();
        self
    }

    /// Whether the device with its hand let go is a member.
    pub fn hand_may_let_go(&self) -> bool {
        self.may_let_go
    }

    /// The reference member: every interval at its low end, every list at its smallest
    /// value, the hand as named. Its mass normalizes the set's walls (module documentation).
    pub fn reference(&self) -> Member {
        Member {
            device: self.device,
            elements: self.elements,
        }
    }

    /// Whether the set has one member only (nothing spread, no hand to let go).
    pub fn is_single(&self) -> bool {
        self.spreads.is_empty() && !self.may_let_go
    }

    /// Whether some parameter takes more than one value (an interval or a list): the set
    /// has several members besides the hand's let-go twin.
    pub fn is_spread(&self) -> bool {
        !self.spreads.is_empty()
    }

    /// Whether some parameter spreads over an interval (a continuum of members).
    pub fn has_intervals(&self) -> bool {
        self.spreads
            .iter()
            .any(|(_, s)| matches!(s, Spread::Interval(..)))
    }

    /// The parameters spread, with their intervals or lists, as reports print them
    /// (`delay 1..3 samples`, `hand mass 0.2, 0.3 kg`), then the hand's assumption.
    pub fn describe(&self) -> Vec<String> {
        let secs = matches!(self.device.delay, Delay::Seconds(_));
        let mut out: Vec<String> = self
            .spreads
            .iter()
            .map(|(p, s)| {
                let v = match s {
                    Spread::Interval(lo, hi) => format!("{lo}..{hi}"),
                    Spread::Values(v) => v
                        .iter()
                        .map(f64::to_string)
                        .collect::<Vec<_>>()
                        .join(" or "),
                };
                format!("{} {v} {}", p.name(), p.unit(secs))
            })
            .collect();
        if self.reference().hand_held() {
            out.push(
                if self.may_let_go {
                    "hand on the handle or let go (the free device is a member)"
                } else {
                    "hand always on the handle (assumed: the free device is not a member)"
                }
                .into(),
            );
        }
        out
    }

    /// How `member` differs within the set: the value of each spread parameter and, when
    /// the hand may let go, whether it holds the handle (`delay = 3 samples; hand off`).
    pub fn describe_member(&self, member: &Member) -> String {
        let secs = matches!(self.device.delay, Delay::Seconds(_));
        let mut parts: Vec<String> = self
            .spreads
            .iter()
            .filter_map(|(p, _)| {
                p.get(&member.device, &member.elements)
                    .map(|v| format!("{} = {v} {}", p.name(), p.unit(secs)))
            })
            .collect();
        if self.may_let_go {
            parts.push(
                if member.hand_held() {
                    "hand on"
                } else {
                    "hand off"
                }
                .into(),
            );
        }
        if parts.is_empty() {
            "the device".into()
        } else {
            parts.join("; ")
        }
    }

    /// This set on the plant `(delta, d)` of a table node: damping `b = delta m_ref / T` and
    /// the delay `d` samples (in the device's unit), the rest as it is.
    ///
    /// # Errors
    ///
    /// When the damping or the delay is spread (a table's axes give them), or the member
    /// at the node is no valid loop.
    pub fn at_plant(&self, delta: f64, d: f64) -> Result<Self> {
        if self
            .spreads
            .iter()
            .any(|(p, _)| matches!(p, Quantity::Damping | Quantity::Delay))
        {
            return Err(Error::InvalidRequest(
                "a lookup table's axes give the damping and the delay: spread only the other parameters over the set".into(),
            ));
        }
        let mut out = self.clone();
        let (m, t) = (self.device.mass, self.device.period);
        out.device.damping = delta * m / t;
        out.device.delay = match self.device.delay {
            Delay::Seconds(_) => Delay::Seconds(d * t),
            Delay::Samples(_) => Delay::Samples(d),
        };
        out.validated()
    }

    /// The boxes of the set: every combination of listed values, with the hand on and
    /// (when it may let go) off; the hand's intervals and lists drop out of the free box.
    pub(crate) fn variants(&self) -> Vec<Variant> {
        let mut combos: Vec<Member> = vec![self.reference()];
        for (p, s) in &self.spreads {
            if let Spread::Values(v) = s {
                combos = combos
                    .iter()
                    .flat_map(|m| {
                        v.iter().map(move |&x| {
                            let mut m = *m;
                            p.set(&mut m.device, &mut m.elements, x);
                            m
                        })
                    })
                    .collect();
            }
        }
        let dims = |hand: bool| -> Vec<(Quantity, f64, f64)> {
            self.spreads
                .iter()
                .filter_map(|(p, s)| match s {
                    Spread::Interval(lo, hi) if hand || !p.is_hand() => Some((*p, *lo, *hi)),
                    _ => None,
                })
                .collect()
        };
        let mut out: Vec<Variant> = combos
            .iter()
            .map(|&base| Variant {
                base,
                dims: dims(true),
            })
            .collect();
        if self.may_let_go {
            let mut free: Vec<Member> = Vec::new();
            for m in &combos {
                let mut m = *m;
                m.elements = hand_let_go(&m.elements).unwrap_or(m.elements);
                // the hand's lists give the same free device several times
                if !free.contains(&m) {
                    free.push(m);
                }
            }
            out.extend(free.into_iter().map(|base| Variant {
                base,
                dims: dims(false),
            }));
        }
        out
    }

    /// A finite sample of the members: every member of a finite set; with intervals, three
    /// values of each (ends and middle) in every combination, or only the corners beyond
    /// three intervals. The conservative check of a lookup table tests its queries on these.
    pub fn sampled_members(&self) -> Vec<Member> {
        let mut out = Vec::new();
        for v in self.variants() {
            let k = v.dims();
            let n = if k <= 3 { 3 } else { 2 };
            out.extend(sample::grid(k, n).iter().map(|p| v.member(p)));
        }
        out
    }

    fn validated(self) -> Result<Self> {
        let intervals = self
            .spreads
            .iter()
            .filter(|(_, s)| matches!(s, Spread::Interval(..)))
            .count();
        if intervals > MAX_INTERVALS {
            return Err(Error::InvalidRequest(format!(
                "{intervals} parameters are spread over intervals; at most {MAX_INTERVALS} are accepted (fix the others at their worst value, or give a list)"
            )));
        }
        let combos: usize = self
            .spreads
            .iter()
            .map(|(_, s)| match s {
                Spread::Values(v) => v.len(),
                Spread::Interval(..) => 1,
            })
            .product::<usize>()
            .saturating_mul(if self.may_let_go { 2 } else { 1 });
        if combos > MAX_VARIANTS {
            return Err(Error::InvalidRequest(format!(
                "the lists of the set give {combos} combinations; at most {MAX_VARIANTS} are accepted"
            )));
        }
        for v in self.variants() {
            for c in v.corners() {
                v.member(&c).to_loop()?;
            }
        }
        Ok(self)
    }
}

/// The elements `named` with the operator's hand let go of the handle (every hand
/// parameter of the element list left out); `None` when no hand is named.
///
/// ```
/// use stabound::elements::PhysicalElements;
/// use stabound::robust::hand_let_go;
///
/// let mut e = PhysicalElements::default();
/// e.hand_mass = Some(0.3);
/// e.velocity_filter_cutoff = Some(50.0);
/// let free = hand_let_go(&e).unwrap();
/// assert_eq!((free.hand_mass, free.velocity_filter_cutoff), (None, Some(50.0)));
/// assert!(hand_let_go(&free).is_none());
/// ```
pub fn hand_let_go(named: &PhysicalElements) -> Option<PhysicalElements> {
    let mut free = *named;
    hand_params().for_each(|p| p.clear(&mut free));
    (free != *named).then_some(free)
}

/// The hand's parameters in the element list.
fn hand_params() -> impl Iterator<Item = &'static list::Param> {
    list::PARAMS
        .iter()
        .filter(|p| p.element == list::Element::Hand)
}

/// The intersection of two sorted lists of disjoint open intervals.
pub(crate) fn intersect(a: &[Interval], b: &[Interval]) -> Vec<Interval> {
    let (mut i, mut j, mut out) = (0, 0, Vec::new());
    while i < a.len() && j < b.len() {
        let lo = a[i].lo.max(b[j].lo);
        let hi = a[i].hi.min(b[j].hi);
        if lo < hi {
            out.push(Interval { lo, hi });
        }
        if a[i].hi < b[j].hi {
            i += 1;
        } else {
            j += 1;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn device() -> Device {
        Device::new(0.1, 1e-3, 1.0, Delay::Samples(1.0)).unwrap()
    }

    #[test]
    fn hand_lets_go_unless_gripped() {
        let e = PhysicalElements {
            hand_mass: Some(0.3),
            ..Default::default()
        };
        let set = DeviceSet::new(&device(), &e).unwrap();
        assert!(set.hand_may_let_go() && !set.is_single());
        let v = set.variants();
        assert_eq!(v.len(), 2);
        assert!(v[0].base.hand_held() && !v[1].base.hand_held());
        let gripped = set.always_gripped(true);
        assert!(gripped.is_single() && gripped.variants().len() == 1);
        // no hand: nothing to let go
        let bare = DeviceSet::new(&device(), &PhysicalElements::default()).unwrap();
        assert!(bare.is_single() && !bare.always_gripped(false).hand_may_let_go());
    }

    #[test]
    fn intervals_lists_and_refusals() {
        let set = DeviceSet::new(&device(), &PhysicalElements::default())
            .unwrap()
            .with_interval(Quantity::Delay, 1.0, 3.0)
            .unwrap()
            .with_values(Quantity::Mass, &[0.11, 0.09])
            .unwrap();
        // the reference takes the low ends
        assert_eq!(set.reference().device().mass(), 0.09);
        let v = set.variants();
        assert_eq!(v.len(), 2);
        assert_eq!(v[0].dims(), 1);
        let top = v[1].member(&[1.0]);
        assert_eq!(top.device().delay(), Delay::Samples(3.0));
        assert_eq!(top.device().mass(), 0.11);
        assert!(
            set.clone()
                .with_interval(Quantity::Delay, 3.0, 1.0)
                .is_err()
        );
        assert!(
            set.clone()
                .with_interval(Quantity::Mass, -1.0, 1.0)
                .is_err()
        );
        assert!(set.clone().with_values(Quantity::Damping, &[]).is_err());
        // a table gives damping and delay itself
        assert!(set.at_plant(0.5, 2.0).is_err());
    }
}
