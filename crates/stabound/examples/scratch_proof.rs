use stabound::elements::PhysicalElements;
use stabound::params::{Delay, Device, Wall};
use stabound::robust::{DeviceSet, Quantity, prove_wall, robust_alpha_max};
fn main() {
    let device = Device::new(0.1, 1e-3, 1.0, Delay::Samples(1.0)).unwrap();
    let mut hand = PhysicalElements::default();
    hand.hand_mass = Some(0.2);
    hand.hand_stiffness = Some(300.0);
    let sets = vec![
        ("hand on/off", DeviceSet::new(&device, &hand).unwrap()),
        (
            "hand mass 0.2..0.5 on/off",
            DeviceSet::new(&device, &hand)
                .unwrap()
                .with_interval(Quantity::element("hand_mass").unwrap(), 0.2, 0.5)
                .unwrap(),
        ),
        (
            "hand mass 0.2..0.5 gripped",
            DeviceSet::new(&device, &hand)
                .unwrap()
                .with_interval(Quantity::element("hand_mass").unwrap(), 0.2, 0.5)
                .unwrap()
                .always_gripped(true),
        ),
        (
            "hand mass x stiffness gripped",
            DeviceSet::new(&device, &hand)
                .unwrap()
                .with_interval(Quantity::element("hand_mass").unwrap(), 0.2, 0.5)
                .unwrap()
                .with_interval(Quantity::element("hand_stiffness").unwrap(), 100.0, 300.0)
                .unwrap()
                .always_gripped(true),
        ),
    ];
    for (name, set) in sets {
        let t = std::time::Instant::now();
        let r = robust_alpha_max(&set, &Default::default()).unwrap();
        println!(
            "{name}: amax {} verified {} by {} in {:?}",
            r.alpha_max,
            r.alpha_verified,
            r.verification.describe(),
            t.elapsed()
        );
        for f in [0.9, 0.99, 0.999] {
            let w = Wall::new(r.alpha_max * f, r.beta_at_max).unwrap();
            let t = std::time::Instant::now();
            let p = prove_wall(&set, &w, 100000).unwrap();
            match p {
                Some(p) => println!(
                    "  {f}: proved {} evaluated {} in {:?}",
                    p.proved,
                    p.evaluated,
                    t.elapsed()
                ),
                None => println!("  {f}: n/a"),
            }
        }
    }
}
