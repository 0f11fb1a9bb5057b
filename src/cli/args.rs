//! Argument types shared by the subcommands.

use clap::ValueEnum;

/// The most values one list may expand to; a request past this would not fit the output in
/// memory for the sweeping commands.
pub const MAX_LIST: usize = 100_000;

/// Parses a list of numbers: a comma list (`0,0.25,0.5`) or an inclusive range
/// `START:STOP:COUNT` of `COUNT` evenly spaced values.
pub fn parse_list(s: &str) -> Result<Vec<f64>, String> {
    let s = s.trim();
    if s.is_empty() {
        return Err("empty list; give values like 0,0.25,0.5 or a range START:STOP:COUNT".into());
    }
    let number = |t: &str| -> Result<f64, String> {
        let v: f64 = t
            .trim()
            .parse()
            .map_err(|_| format!("'{t}' is not a number"))?;
        if !v.is_finite() {
            return Err(format!("'{t}' is not a finite number"));
        }
        Ok(v)
    };
    if s.contains(':') {
        let parts: Vec<&str> = s.split(':').collect();
        if parts.len() != 3 {
            return Err(format!("range '{s}' must be START:STOP:COUNT, e.g. 0:1:11"));
        }
        let start = number(parts[0])?;
        let stop = number(parts[1])?;
        let count: usize = parts[2].trim().parse().map_err(|_| {
            format!(
                "COUNT '{}' in range '{s}' must be a whole number >= 1",
                parts[2]
            )
        })?;
        if count == 0 || count > MAX_LIST {
            return Err(format!(
                "COUNT in range '{s}' must be between 1 and {MAX_LIST}"
            ));
        }
        if stop < start {
            return Err(format!("range '{s}' is inverted: STOP must be >= START"));
        }
        if count == 1 {
            return Ok(vec![start]);
        }
        let step = (stop - start) / (count - 1) as f64;
        let mut v: Vec<f64> = (0..count).map(|i| start + step * i as f64).collect();
        v[count - 1] = stop;
        return Ok(v);
    }
    let v: Vec<f64> = s.split(',').map(number).collect::<Result<_, _>>()?;
    if v.len() > MAX_LIST {
        return Err(format!(
            "list has {} values; at most {MAX_LIST} are accepted",
            v.len()
        ));
    }
    Ok(v)
}

/// Stability test method, as named on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum MethodArg {
    /// Schur-Cohn with a rounding-error guard, state-space eigenvalues when it cannot vouch.
    Auto,
    /// Normalized Schur-Cohn recursion (fast, no roots).
    SchurCohn,
    /// Companion-matrix eigenvalues.
    Eigen,
    /// Closed-loop state-matrix eigenvalues (best for long delays).
    StateSpace,
}

impl From<MethodArg> for stabound::stability::Method {
    fn from(m: MethodArg) -> Self {
        match m {
            MethodArg::Auto => Self::Auto,
            MethodArg::SchurCohn => Self::SchurCohn,
            MethodArg::Eigen => Self::Eigen,
            MethodArg::StateSpace => Self::StateSpace,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_and_ranges() {
        assert_eq!(parse_list("0,0.25, 0.5").unwrap(), vec![0.0, 0.25, 0.5]);
        assert_eq!(
            parse_list("0:1:5").unwrap(),
            vec![0.0, 0.25, 0.5, 0.75, 1.0]
        );
        assert_eq!(parse_list("2:2:1").unwrap(), vec![2.0]);
        for bad in [
            "", "a", "1,,2", "1:0:3", "0:1:0", "0:1", "nan", "inf", "0:1:1e9",
        ] {
            assert!(parse_list(bad).is_err(), "{bad}");
        }
    }
}
