//! `check --certify` and `amax --certify` over a finite set of devices: one certificate of
//! kind `set` holding every member's proof, which the standalone checker
//! (`tools/verify_certificate.py`) replays member by member. The verdicts are judged
//! independently by the eigenvalues of each member's closed-loop state matrix
//! ([`crate::robust_sets::stable`]); a certificate with a member changed, dropped,
//! duplicated or taken from another set is rejected.

use std::path::Path;

use crate::amax_certify::certified;
use crate::certified_table::{from_hex, rejected_after, verify};
use crate::common::{assert_bad_input, csv, stabound};
use crate::robust_sets::stable;
use stabound::elements::PhysicalElements;
use stabound::params::{Delay, Device};

/// The 0.1 kg device at 1 ms with one sample of delay and no damping.
pub(crate) const DEVICE: [&str; 8] = [
    "--mass",
    "0.1",
    "--period",
    "0.001",
    "--damping",
    "0",
    "--delay-samples",
    "1",
];

/// A hand of 2 N s/m and 300 N/m on the handle, of 0.2 or 0.3 kg (`check` judges the hands
/// its flags name: both held).
const HANDS: [&str; 6] = [
    "--hand-mass",
    "one-of:0.2,0.3",
    "--hand-damping",
    "2",
    "--hand-stiffness",
    "300",
];

fn device() -> Device {
    Device::new(0.1, 0.001, 0.0, Delay::Samples(1.0)).unwrap()
}

/// The held hand of `mass` kg (`None`: the hand let go), behind a velocity filter of
/// `cutoff` Hz when given.
fn hand(mass: Option<f64>, cutoff: Option<f64>) -> PhysicalElements {
    let mut e = PhysicalElements::default();
    e.velocity_filter_cutoff = cutoff;
    if let Some(m) = mass {
        e.hand_mass = Some(m);
        e.hand_damping = Some(2.0);
        e.hand_stiffness = Some(300.0);
    }
    e
}

/// Runs `check` with `args` and `--certify path --format json`: the report.
fn check_json(args: &[&str], path: &Path) -> serde_json::Value {
    let out = stabound()
        .arg("check")
        .args(DEVICE)
        .args(args)
        .args(["--format", "json", "--certify"])
        .arg(path)
        .output()
        .unwrap();
    assert!(out.status.success(), "{args:?}: {out:?}");
    serde_json::from_slice(&out.stdout).unwrap()
}

/// The hand mass in a member's name (`hand mass = 0.3 kg`).
fn mass_of(name: &str) -> f64 {
    let v = name.split(" = ").nth(1).unwrap();
    v.trim_end_matches(" kg").parse().unwrap()
}

/// A wall checked for both held hands: at 2,000 N/m both are stable by eigenvalues and the
/// certificate proves the set stable; at 4,600 N/m (5 N s/m) the 0.2 kg hand is unstable
/// and the 0.3 kg one stable by eigenvalues, and the certificate proves the set unstable
/// and names the 0.2 kg member. The checker accepts both.
#[test]
fn check_over_a_hand_list_is_certified_stable_and_unstable() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("set.json");
    let masses = [0.2, 0.3];
    for (k, want) in [(2000.0, "stable"), (4600.0, "unstable")] {
        let ks = k.to_string();
        let report = check_json(
            &[&HANDS[..], &["--stiffness", &ks, "--wall-damping", "5"]].concat(),
            &path,
        );
        let verdict = report["verdict"].as_str().unwrap();
        assert_eq!(report["members"], 2, "{report}");
        let eig: Vec<bool> = masses
            .iter()
            .map(|&m| stable(&device(), &hand(Some(m), None), k, 5.0))
            .collect();
        let (code, out, err) = verify(&path);
        assert_eq!(code, 0, "{err}");
        if want == "stable" {
            assert_eq!(verdict, "stable for every member of the set");
            assert_eq!(eig, [true, true]);
            assert!(
                out.contains("stable for each of the set's 2 devices"),
                "{out}"
            );
        } else {
            assert_eq!(verdict, "unstable for a member of the set");
            assert_eq!(eig, [false, true]);
            let m = mass_of(report["deciding_member"].as_str().unwrap());
            // exact: the name prints the listed value, which reads back as the same double
            assert_eq!(m, 0.2, "the unstable member");
            assert!(
                out.contains("unstable for the set of 2 devices: member"),
                "{out}"
            );
        }
    }
}

/// A box of walls (500 to 1,000 N/m, 2 to 5 N s/m) for both held hands: certified stable at
/// every wall for every member; the eigenvalues find the corners and the centre stable for
/// both, and the checker accepts it.
#[test]
fn check_over_a_hand_list_certifies_a_box() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("box.json");
    let args = [
        &HANDS[..],
        &["--stiffness", "500..1000", "--wall-damping", "2..5"],
    ]
    .concat();
    let report = check_json(&args, &path);
    assert_eq!(
        report["verdict"],
        "stable for every member of the set at every wall of the box"
    );
    for m in [0.2, 0.3] {
        for (k, b) in [
            (500.0, 2.0),
            (500.0, 5.0),
            (1000.0, 2.0),
            (1000.0, 5.0),
            (750.0, 3.5),
        ] {
            assert!(
                stable(&device(), &hand(Some(m), None), k, b),
                "{m} kg, {k}, {b}"
            );
        }
    }
    let (code, out, err) = verify(&path);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("stable for each of the set's 2 devices"),
        "{out}"
    );
}

/// The certificate of the unstable wall, changed (its CRC made to match again): a digit of
/// a member's coefficient, the claim's verdict, a member dropped or duplicated, and a member
/// taken from another set's certificate (hands of 0.2 or 0.4 kg) are each rejected.
#[test]
fn a_set_certificate_changed_is_rejected() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("set.json");
    let other = dir.path().join("other.json");
    let wall = ["--stiffness", "4600", "--wall-damping", "5"];
    let mut hands = HANDS;
    hands[1] = "one-of:0.2,0.4";
    check_json(&[&hands[..], &wall].concat(), &other);
    check_json(&[&HANDS[..], &wall].concat(), &path);
    let original = std::fs::read_to_string(&path).unwrap();
    let restore = || std::fs::write(&path, &original).unwrap();
    let rewrite = |edit: &str| {
        format!("\ncert = json.loads(text)\n{edit}\nbody = json.dumps(cert, indent=2) + \"\\n\"")
    };
    let digit = r#"
c = cert['members'][1]['coefficients'][0]
m = c['mid']
i = m.index('.') + 1
c['mid'] = m[:i] + format((int(m[i], 16) + 3) % 16, 'x') + m[i + 1:]"#;
    let err = rejected_after(&path, &rewrite(digit));
    assert!(err.contains("member 1:"), "{err}");
    restore();
    let err = rejected_after(
        &path,
        &rewrite("cert['claim']['verdict'] = 'stable'; del cert['claim']['member']"),
    );
    assert!(err.contains("the members prove unstable"), "{err}");
    restore();
    let foreign = format!(
        "cert['members'][1] = json.load(open({:?}))['members'][1]",
        other.to_str().unwrap()
    );
    for edit in [
        "del cert['members'][1]",
        "cert['members'].append(cert['members'][0])",
        foreign.as_str(),
    ] {
        let err = rejected_after(&path, &rewrite(edit));
        assert!(err.contains("members are not the set's 2"), "{edit}: {err}");
        restore();
    }
}

/// Two lists (hand 0.2 or 0.3 kg, filter 30 or 100 Hz) at 1,500 N/m and 5 N s/m: the four
/// members are stable by eigenvalues, the certificate proves the set stable and the checker
/// accepts it; two members swapped (no longer in the order of the combinations) are
/// rejected.
#[test]
fn two_lists_make_four_members_in_order() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("four.json");
    let args = [
        &HANDS[..],
        &["--velocity-filter-cutoff", "one-of:30,100"],
        &["--stiffness", "1500", "--wall-damping", "5"],
    ]
    .concat();
    let report = check_json(&args, &path);
    assert_eq!(report["verdict"], "stable for every member of the set");
    assert_eq!(report["members"], 4);
    for m in [0.2, 0.3] {
        for c in [30.0, 100.0] {
            assert!(
                stable(&device(), &hand(Some(m), Some(c)), 1500.0, 5.0),
                "{m} kg, {c} Hz"
            );
        }
    }
    let (code, out, err) = verify(&path);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("stable for each of the set's 4 devices"),
        "{out}"
    );
    let swap = "\ncert = json.loads(text)\nm = cert['members']\nm[1], m[2] = m[2], m[1]\nbody = json.dumps(cert, indent=2) + \"\\n\"";
    let err = rejected_after(&path, swap);
    assert!(err.contains("members are not the set's 4"), "{err}");
}

/// The robust alpha_max of the 0.1 kg device behind a 50 Hz velocity filter, held by a
/// 0.3 kg hand that can let go, dampings 0 to 100 N s/m: the enclosure holds the row's
/// K_max, the wall at its lower end is stable with the hand on and off by eigenvalues, and
/// at its upper end no damping of a grid of 101 over the range is stable for both. The
/// checker accepts the certificate and the row's enclosure is the one it verified; the
/// binding member's index changed is rejected. The command's message names the binding
/// member.
#[test]
fn amax_over_a_hand_that_lets_go_is_certified() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("amax.json");
    let out = stabound()
        .arg("amax")
        .args(DEVICE)
        .args(&HANDS[2..])
        .args(["--hand-mass", "0.3", "--velocity-filter-cutoff", "50"])
        .args([
            "--wall-damping-min",
            "0",
            "--wall-damping-max",
            "100",
            "--certify",
        ])
        .arg(&path)
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    // the message names the member whose proof the certificate holds (members: the hand
    // on, then off)
    let cert: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let binding = ["hand on", "hand off"][cert["claim"]["member"].as_u64().unwrap() as usize];
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(
        said.contains(&format!(
            "enclosure is one member's proof: {binding} binds over the whole damping range"
        )),
        "{said}"
    );
    let (head, rows) = csv(&out.stdout);
    let col = |name: &str| -> f64 {
        let i = head.split(',').position(|c| c == name).unwrap();
        rows[0][i].parse().unwrap()
    };
    let (k_lo, k_hi, _, b) = enclosure(&col);
    let members = [hand(Some(0.3), Some(50.0)), hand(None, Some(50.0))];
    for m in &members {
        assert!(stable(&device(), m, k_lo, b), "{m:?} at K_lo");
    }
    some_member_unstable(&members, k_hi);
    let (code, text, err) = verify(&path);
    assert_eq!(code, 0, "{err}");
    assert!(
        text.contains("robust alpha_max of the set's 2 devices"),
        "{text}"
    );
    let alpha = |name: &str| col(name);
    let enclosure = format!(
        "[{:?}, {:?}]",
        alpha("alpha_lo_certified"),
        alpha("alpha_hi_certified")
    );
    assert!(text.contains(&enclosure), "{text}: {enclosure}");
    let edit = "\ncert = json.loads(text)\ncert['claim']['member'] = 1 - cert['claim']['member']\nbody = json.dumps(cert, indent=2) + \"\\n\"";
    let err = rejected_after(&path, edit);
    assert!(err.contains("binding member"), "{err}");
}

/// The device behind a compliant transmission (a 0.02 kg handle, 1 N s/m of coupling
/// damping) of 2,000 or 5,000 N/m, dampings 0 to 100 N s/m: the members' limits cross at the
/// robust optimum, so the upper end is proved in pieces of the damping range. The enclosure
/// holds the row's K_max within 1e-4 of it; by eigenvalues both members are stable at its
/// lower end, and at its upper end every damping of a grid of 101 has a member unstable
/// while each member alone has a stable damping there (its own K_max lies above). The
/// checker accepts the certificate, and rejects it with a middle piece dropped (a gap), the
/// first piece dropped (the range not covered from its start), a piece's end moved, and a
/// digit of a piece's leaf changed. The command's message tells the pieces as the
/// certificate holds them (the runs of one member, their ends in N s/m).
#[test]
fn amax_where_two_members_limits_cross_is_certified_in_pieces() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cross.json");
    let coupling = ["--handle-mass", "0.02", "--transmission-damping", "1"];
    let range = ["--wall-damping-min", "0", "--wall-damping-max", "100"];
    let said = std::cell::RefCell::new(String::new());
    let run = |stiffness: &str, certify: bool| {
        let mut cmd = stabound();
        cmd.arg("amax").args(DEVICE).args(coupling).args(range);
        cmd.args(["--transmission-stiffness", stiffness]);
        if certify {
            cmd.arg("--certify").arg(&path);
        }
        let out = cmd.output().unwrap();
        assert!(out.status.success(), "{out:?}");
        *said.borrow_mut() = String::from_utf8_lossy(&out.stderr).into_owned();
        let (head, rows) = csv(&out.stdout);
        let cols: Vec<String> = head.split(',').map(str::to_string).collect();
        move |name: &str| -> f64 {
            let i = cols.iter().position(|c| c == name).unwrap();
            rows[0][i].parse().unwrap()
        }
    };
    let col = run("one-of:2000,5000", true);
    pieces_told(&said.borrow(), &path, &["2000", "5000"]);
    let (k_lo, k_hi, k_max, b) = enclosure(&col);
    assert!(k_hi <= k_max * (1.0 + 1.001e-4), "{k_max} {k_hi}");
    let member = |k: f64| {
        let mut e = PhysicalElements::default();
        e.handle_mass = Some(0.02);
        e.transmission_damping = Some(1.0);
        e.transmission_stiffness = Some(k);
        e
    };
    let members = [member(2000.0), member(5000.0)];
    for (m, k) in members.iter().zip(["2000", "5000"]) {
        assert!(stable(&device(), m, k_lo, b), "{k} N/m at K_lo");
        assert!(run(k, false)("K_max_N_per_m") > k_hi, "{k} N/m alone");
    }
    some_member_unstable(&members, k_hi);
    let (code, text, err) = verify(&path);
    assert_eq!(code, 0, "{err}");
    let enclosure = format!(
        "in [{:?}, {:?}]",
        col("alpha_lo_certified"),
        col("alpha_hi_certified")
    );
    assert!(text.contains(&enclosure), "{text}: {enclosure}");
    assert!(text.contains("or any stiffer wall ("), "{text}");
    let original = std::fs::read_to_string(&path).unwrap();
    let edit = |e: &str| {
        format!(
            "\ncert = json.loads(text)\nps = cert['pieces']\n{e}\nbody = json.dumps(cert, indent=2) + \"\\n\""
        )
    };
    let digit = r#"
c = ps[1]['unstable_above']['leaves'][0]['coefficients'][0]
m = c['mid']
i = m.index('.') + 1
c['mid'] = m[:i] + format((int(m[i], 16) + 3) % 16, 'x') + m[i + 1:]"#;
    let moved = r#"
b = ps[0]['unstable_above']['inputs']['beta']
m, e = float.hex(float.fromhex(b[1]) * 0.99).split('p')
b[1] = m.rstrip('0').rstrip('.') + 'p' + e"#;
    for (change, why) in [
        ("del ps[len(ps) // 2]", "do not meet end to end"),
        ("del ps[0]", "do not meet end to end"),
        (moved, "piece 0:"),
        (digit, "piece 1:"),
    ] {
        let err = rejected_after(&path, &edit(change));
        assert!(err.contains(why), "{change}: {err}");
        std::fs::write(&path, &original).unwrap();
    }
}

/// Asserts that `said`, the stderr of `amax --certify` over a set whose certificate at
/// `path` proves its upper end in pieces, tells them as the certificate holds them: their
/// count, and each run of consecutive pieces of one member as its damping range in N s/m
/// (the 0.1 kg device at 1 ms: B = 100 beta) and the member, named by the value of
/// `values` (transmission stiffnesses in N/m, in the set's order) it has.
fn pieces_told(said: &str, path: &Path, values: &[&str]) {
    let cert: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let pieces = cert["pieces"].as_array().unwrap();
    let hex = |v: &serde_json::Value| from_hex(v.as_str().unwrap());
    let mut runs: Vec<(f64, f64, usize, usize)> = Vec::new();
    for p in pieces {
        let beta = &p["unstable_above"]["inputs"]["beta"];
        let (lo, hi) = (hex(&beta[0]), hex(&beta[1]));
        let member = p["member"].as_u64().unwrap() as usize;
        match runs.last_mut() {
            Some(run) if run.2 == member => (run.1, run.3) = (hi, run.3 + 1),
            _ => runs.push((lo, hi, member, 1)),
        }
    }
    assert!(runs.len() > 1, "{runs:?}");
    let line = said
        .lines()
        .find(|l| l.contains("upper end"))
        .unwrap_or_else(|| panic!("{said}"));
    assert!(
        line.contains(&format!(
            "proved in {} pieces of the damping range",
            pieces.len()
        )),
        "{line}"
    );
    let told: Vec<&str> = line.rsplit_once(": ").unwrap().1.split(", then ").collect();
    assert_eq!(told.len(), runs.len(), "{line}");
    for (text, &(lo, hi, member, n)) in told.iter().zip(&runs) {
        let (ends, rest) = text.split_once("] N s/m by ").unwrap();
        let (a, b) = ends.trim_start_matches('[').split_once(", ").unwrap();
        // the message's ends are the certificate's scaled by m / T = 100: two roundings of
        // the product and the shortest decimal that reads back, a few units of 2^-53
        // relative, well inside 1e-12
        for (shown, beta) in [(a, lo), (b, hi)] {
            let shown: f64 = shown.parse().unwrap();
            assert!(
                (shown - 100.0 * beta).abs() <= 1e-12 * (1.0 + shown.abs()),
                "{text}"
            );
        }
        let name = format!("transmission stiffness = {} N/m", values[member]);
        assert!(rest.starts_with(&name), "{text}: {name}");
        assert_eq!(rest.contains(&format!("({n} pieces)")), n > 1, "{text}");
    }
}

/// The row's certified enclosure, K_max and its damping, `(K_lo, K_hi, K_max, B)`, read by
/// `col`, K_max asserted within the enclosure.
pub(crate) fn enclosure(col: &dyn Fn(&str) -> f64) -> (f64, f64, f64, f64) {
    let (k_lo, k_hi, k_max, b) = (
        col("K_lo_certified_N_per_m"),
        col("K_hi_certified_N_per_m"),
        col("K_max_N_per_m"),
        col("B_at_max_Ns_per_m"),
    );
    assert!(k_lo <= k_max && k_max < k_hi, "{k_lo} {k_max} {k_hi}");
    (k_lo, k_hi, k_max, b)
}

/// Asserts that at the stiffness `k_hi` (N/m) every wall damping of 0, 1, ..., 100 N s/m has
/// a member of `members` unstable by eigenvalues.
fn some_member_unstable(members: &[PhysicalElements], k_hi: f64) {
    for i in 0..=100 {
        let bw = f64::from(i);
        assert!(
            members.iter().any(|m| !stable(&device(), m, k_hi, bw)),
            "B = {bw} at K_hi"
        );
    }
}

/// Sets the certificate does not cover are refused as bad input before any file is
/// written: an interval of hand masses (`amax`).
#[test]
fn set_certify_refusals() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.json");
    let p = path.to_str().unwrap();
    let mut interval: Vec<&str> = vec!["amax"];
    interval.extend(DEVICE);
    interval.extend(["--hand-mass", "0.2..0.3", "--wall-damping-min", "0"]);
    interval.extend(["--wall-damping-max", "100", "--certify", p]);
    assert_bad_input(&interval, true);
    assert!(!path.exists());
}

/// Two rows of the compliant transmission's set (dampings 0 and 0.1 N s/m of the device),
/// each robust alpha_max's upper end proved in pieces: the checker accepts the grid's one
/// certificate, row by row, and the command tells each row's pieces on a line naming the
/// row.
#[test]
fn a_grid_of_sets_proved_in_pieces_is_accepted_row_by_row() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("rows.json");
    let mut args = vec!["amax"];
    args.extend(DEVICE);
    args[6] = "0,0.1";
    args.extend(["--handle-mass", "0.02", "--transmission-damping", "1"]);
    args.extend(["--transmission-stiffness", "one-of:2000,5000"]);
    args.extend(["--wall-damping-min", "0", "--wall-damping-max", "100"]);
    let (_, said) = certified(&args, &path);
    for row in ["(delta = 0, d = 1)", "(delta = 0.001, d = 1)"] {
        let line = said.lines().find(|l| l.contains(row)).unwrap_or("");
        assert!(
            line.contains(" pieces of the damping range"),
            "{row}: {said}"
        );
    }
    let (code, text, err) = verify(&path);
    assert_eq!(code, 0, "{err}");
    assert!(text.starts_with("verified: 2 rows"), "{text}");
    assert_eq!(
        text.matches("stabilizes alpha_hi or any stiffer wall (")
            .count(),
        2,
        "{text}"
    );
}
