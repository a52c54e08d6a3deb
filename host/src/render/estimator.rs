//! What a Metropolis chain's state is a sample of — the seed's multiplexed paths
//! (`shared::mmlt`) or the path tracer's whole estimate (`shared::pssmlt`) — and the name of a
//! method with its estimator on the command line: `s3` is the speculative tree of depth 3 over
//! the multiplexed estimator, `path-s3` the same tree over the path estimator.

use std::str::FromStr;

use shared::mmlt::{ESTIMATOR_MULTIPLEXED, ESTIMATOR_PATH};

use super::Method;

/// What a chain's state is a sample of.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Estimator {
    /// Multiplexed MLT (the seed's): one technique of one path depth per sample, the depth part
    /// of the state.
    #[default]
    Multiplexed,
    /// Primary-sample-space MLT over the path tracer: each sample is a whole path-traced
    /// estimate (every depth, light sampling and BSDF sampling with MIS).
    Path,
}

impl Estimator {
    /// The `RenderParams::estimator` code.
    pub fn code(self) -> u32 {
        match self {
            Estimator::Multiplexed => ESTIMATOR_MULTIPLEXED,
            Estimator::Path => ESTIMATOR_PATH,
        }
    }
}

/// A method and the estimator its chains sample, as one name: `pt`, `naive`, `s<d>`, `rc<l>`,
/// or `path-naive`, `path-s<d>`, `path-rc<l>`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Sampler {
    #[allow(missing_docs)] // named for what it is
    pub method: Method,
    #[allow(missing_docs)] // named for what it is (the path tracer's is Multiplexed, unused)
    pub estimator: Estimator,
}

/// The prefix naming the path estimator.
const PATH_PREFIX: &str = "path-";

impl std::fmt::Display for Sampler {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.estimator {
            Estimator::Multiplexed => write!(f, "{}", self.method),
            Estimator::Path => write!(f, "{PATH_PREFIX}{}", self.method),
        }
    }
}

impl FromStr for Sampler {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let hint = |e: String| {
            if e.contains("is not a method") {
                format!(
                    "'{s}' is not a method: use pt, naive, s<d> (d in 1..=8) or rc<l> (l in 2..=64), \
                     the last three also as path-<method>"
                )
            } else {
                e
            }
        };
        match s.strip_prefix(PATH_PREFIX) {
            Some(rest) => match rest.parse::<Method>().map_err(hint)? {
                Method::PathTracer => Err(format!("'{s}': the path tracer has no chains; use pt")),
                method => Ok(Sampler { method, estimator: Estimator::Path }),
            },
            None => Ok(Sampler { method: s.parse().map_err(hint)?, estimator: Estimator::Multiplexed }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_and_print() {
        for (name, method, estimator) in [
            ("pt", Method::PathTracer, Estimator::Multiplexed),
            ("s3", Method::Tree(3), Estimator::Multiplexed),
            ("path-naive", Method::Tree(1), Estimator::Path),
            ("path-s3", Method::Tree(3), Estimator::Path),
            ("path-rc16", Method::RejectChain(16), Estimator::Path),
        ] {
            let s: Sampler = name.parse().unwrap();
            assert_eq!(s, Sampler { method, estimator }, "{name}");
            assert_eq!(s.to_string(), name);
        }
        for bad in ["path-pt", "path-", "path-s0", "path", "paths-s3", "path-path-s3"] {
            assert!(bad.parse::<Sampler>().is_err(), "{bad}");
        }
        // The user's own word is named back.
        let e = "path-foo".parse::<Sampler>().unwrap_err();
        assert!(e.starts_with("'path-foo' is not a method") && e.contains("path-<method>"), "{e}");
    }
}
