//! The crate's error type.

use thiserror::Error;

/// Everything the library can refuse or fail at.
///
/// Every message names the input at fault and says what is accepted, so a command-line
/// front end can print it as it is.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum Error {
    /// A parameter is NaN, infinite, or outside its accepted range.
    #[error("invalid {name} = {}: {expected}", crate::shown::Shown(*.value))]
    InvalidParameter {
        /// The parameter's name, as the user would type it (`alpha`, `mass`, ...).
        name: &'static str,
        /// The value that was given.
        value: f64,
        /// What would have been accepted.
        expected: String,
    },
    /// A request is malformed in a way that is not one number out of range
    /// (an empty list, an inverted range, too many points).
    #[error("{}", crate::shown::numbers_shown(.0))]
    InvalidRequest(String),
    /// A request is refused as a whole or one of its inputs (the module [`crate::request`]);
    /// a front end words it with its own spelling of the inputs
    /// ([`crate::request::RequestError::message`]).
    #[error("{0}")]
    Request(crate::inputs::RequestError),
    /// An iterative numerical method did not converge within its iteration cap.
    #[error(
        "{method} did not converge after {iterations} iterations; try another point-test method (for example Schur-Cohn)"
    )]
    NoConvergence {
        /// The method that failed.
        method: &'static str,
        /// The cap that was reached.
        iterations: usize,
    },
    /// A numerical result could not be trusted and no fallback held.
    #[error("numerical failure: {}", crate::shown::numbers_shown(.0))]
    Numerical(String),
    /// The computation was stopped before it was complete by an installed
    /// [`crate::Cancel`]: cancelled, or past its time limit.
    #[error(
        "{}",
        match .time_limit {
            Some(s) => format!("stopped at the time limit of {} s before the computation was complete; allow more time or ask for less (a coarser tolerance, fewer values, fewer walls)", crate::shown::Shown(*s)),
            None => "cancelled before the computation was complete".to_string(),
        }
    )]
    Cancelled {
        /// The time limit in seconds when it ran out; `None` when cancelled.
        time_limit: Option<f64>,
    },
    /// Reading or writing a file failed.
    #[error("{0}")]
    Io(String),
}

/// Shorthand for results of this crate.
pub type Result<T> = std::result::Result<T, Error>;
