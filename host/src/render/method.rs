//! A render's method as the command line names it: the path tracer (`pt`), or the paper's
//! Metropolis chains — parallelised the naive way, as a speculative tree of depth d or as a
//! reject chain of length l ([`Schedule`]) — over the paper's multiplexed paths or the path
//! tracer's estimate ([`Estimator`]): `s3` is the tree of depth 3 over multiplexed paths,
//! `path-s3` the same tree over the path estimator.

use std::str::FromStr;

use serde::{Deserialize, Serialize};
use shared::params::{candidates_per_chain, METHOD_REJECT_CHAIN, METHOD_TREE};
use shared::reject_chain::MAX_REJECT_CHAIN;
use shared::tree::MAX_TREE_DEPTH;

use super::Estimator;

/// How the Metropolis chains are parallelised (the paper's three versions).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Schedule {
    /// Speculative tree of depth d (`s<d>`); d = 1 is the naive parallel MMLT (`naive`).
    Tree(u32),
    /// Reject chain of l proposals (`rc<l>`).
    RejectChain(u32),
}

impl Schedule {
    /// The naive parallel version: one candidate per chain and iteration.
    pub const NAIVE: Schedule = Schedule::Tree(1);

    /// Candidates traced per chain and iteration.
    pub fn candidates_per_chain(self) -> u32 {
        match self {
            Schedule::Tree(d) => candidates_per_chain(METHOD_TREE, d, 0),
            Schedule::RejectChain(l) => candidates_per_chain(METHOD_REJECT_CHAIN, 1, l),
        }
    }

    /// The `RenderParams::method` code.
    pub fn code(self) -> u32 {
        match self {
            Schedule::Tree(_) => METHOD_TREE,
            Schedule::RejectChain(_) => METHOD_REJECT_CHAIN,
        }
    }

    /// The tree's depth (1 for a reject chain, whose proposals form no tree).
    pub fn tree_depth(self) -> u32 {
        match self {
            Schedule::Tree(d) => d,
            Schedule::RejectChain(_) => 1,
        }
    }

    /// The reject chain's length (0 for a tree).
    pub fn reject_length(self) -> u32 {
        match self {
            Schedule::Tree(_) => 0,
            Schedule::RejectChain(l) => l,
        }
    }
}

impl std::fmt::Display for Schedule {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Schedule::Tree(1) => write!(f, "naive"),
            Schedule::Tree(d) => write!(f, "s{d}"),
            Schedule::RejectChain(l) => write!(f, "rc{l}"),
        }
    }
}

/// What every method's name error ends with.
const METHODS: &str =
    "use auto, pt, naive, s<d> (d in 1..=8) or rc<l> (l in 2..=64), the last three also as path-<method>";

impl FromStr for Schedule {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        if s == "naive" {
            return Ok(Schedule::NAIVE);
        }
        if let Some(d) = s.strip_prefix('s') {
            return match d.parse::<u32>() {
                Ok(d) if (1..=MAX_TREE_DEPTH).contains(&d) => Ok(Schedule::Tree(d)),
                _ => Err(format!(
                    "'{s}': the speculative tree depth must be 1..={MAX_TREE_DEPTH} (s1..s{MAX_TREE_DEPTH})"
                )),
            };
        }
        if let Some(l) = s.strip_prefix("rc") {
            return match l.parse::<u32>() {
                Ok(l) if (2..=MAX_REJECT_CHAIN).contains(&l) => Ok(Schedule::RejectChain(l)),
                _ => Err(format!(
                    "'{s}': the reject-chain length must be 2..={MAX_REJECT_CHAIN} (rc2..rc{MAX_REJECT_CHAIN})"
                )),
            };
        }
        Err(format!("'{s}' is not a method: {METHODS}"))
    }
}

/// A render's method, as named on the command line: `pt`, `naive`, `s<d>`, `rc<l>`, or
/// `path-naive`, `path-s<d>`, `path-rc<l>`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// The path tracer: independent samples of every pixel, no chains.
    PathTracer,
    /// Metropolis chains parallelised by `schedule`, sampling `estimator`.
    Metropolis {
        #[allow(missing_docs)] // how the chains are parallelised
        schedule: Schedule,
        #[allow(missing_docs)] // what the chains sample
        estimator: Estimator,
    },
}

/// The prefix naming the path estimator.
const PATH_PREFIX: &str = "path-";

impl Method {
    /// The paper's naive parallel MMLT (the default).
    pub const NAIVE: Method =
        Method::Metropolis { schedule: Schedule::NAIVE, estimator: Estimator::Multiplexed };
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Method::PathTracer => write!(f, "pt"),
            Method::Metropolis { schedule, estimator: Estimator::Multiplexed } => write!(f, "{schedule}"),
            Method::Metropolis { schedule, estimator: Estimator::Path } => {
                write!(f, "{PATH_PREFIX}{schedule}")
            }
        }
    }
}

impl FromStr for Method {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let named_back = |e: String| {
            if e.contains("is not a method") {
                format!("'{s}' is not a method: {METHODS}")
            } else {
                e
            }
        };
        if s == "pt" {
            return Ok(Method::PathTracer);
        }
        match s.strip_prefix(PATH_PREFIX) {
            Some("pt") => Err(format!("'{s}': the path tracer has no chains; use pt")),
            Some(rest) => Ok(Method::Metropolis {
                schedule: rest.parse().map_err(named_back)?,
                estimator: Estimator::Path,
            }),
            None => Ok(Method::Metropolis {
                schedule: s.parse().map_err(named_back)?,
                estimator: Estimator::Multiplexed,
            }),
        }
    }
}

/// `--method` as the command line takes it: `auto`, chosen for the view by a pilot
/// (`super::auto`), or a [`Method`] named.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MethodChoice {
    /// Chosen by the pilot.
    Auto,
    /// The method named.
    Named(Method),
}

impl std::fmt::Display for MethodChoice {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            MethodChoice::Auto => write!(f, "auto"),
            MethodChoice::Named(m) => write!(f, "{m}"),
        }
    }
}

impl FromStr for MethodChoice {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        if s == "auto" {
            return Ok(MethodChoice::Auto);
        }
        s.parse().map(MethodChoice::Named)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_and_print() {
        let tree = |d, estimator| Method::Metropolis { schedule: Schedule::Tree(d), estimator };
        let rc = |l, estimator| Method::Metropolis { schedule: Schedule::RejectChain(l), estimator };
        for (name, method, printed) in [
            ("pt", Method::PathTracer, "pt"),
            ("naive", tree(1, Estimator::Multiplexed), "naive"),
            ("s1", tree(1, Estimator::Multiplexed), "naive"),
            ("s3", tree(3, Estimator::Multiplexed), "s3"),
            ("s8", tree(8, Estimator::Multiplexed), "s8"),
            ("rc2", rc(2, Estimator::Multiplexed), "rc2"),
            ("rc64", rc(64, Estimator::Multiplexed), "rc64"),
            ("path-naive", tree(1, Estimator::Path), "path-naive"),
            ("path-s3", tree(3, Estimator::Path), "path-s3"),
            ("path-rc16", rc(16, Estimator::Path), "path-rc16"),
        ] {
            let m: Method = name.parse().unwrap();
            assert_eq!(m, method, "{name}");
            assert_eq!(m.to_string(), printed);
        }
        for bad in [
            "s0",
            "s9",
            "rc1",
            "rc65",
            "tree",
            "",
            "s",
            "rc",
            "pt1",
            "PT",
            "path-pt",
            "path-",
            "path-s0",
            "path",
            "paths-s3",
            "path-path-s3",
        ] {
            assert!(bad.parse::<Method>().is_err(), "{bad}");
        }
        // The user's own word is named back.
        let e = "path-foo".parse::<Method>().unwrap_err();
        assert!(e.starts_with("'path-foo' is not a method") && e.contains("path-<method>"), "{e}");
    }

    #[test]
    fn auto_or_a_method_named() {
        assert_eq!("auto".parse::<MethodChoice>(), Ok(MethodChoice::Auto));
        assert_eq!("path-s3".parse::<MethodChoice>().unwrap().to_string(), "path-s3");
        assert_eq!("pt".parse::<MethodChoice>(), Ok(MethodChoice::Named(Method::PathTracer)));
        assert!("auto".parse::<Method>().is_err(), "auto is no method of its own");
        let e = "Auto".parse::<MethodChoice>().unwrap_err();
        assert!(e.starts_with("'Auto' is not a method: use auto, pt"), "{e}");
    }

    #[test]
    fn candidates_per_chain() {
        assert_eq!(Schedule::Tree(1).candidates_per_chain(), 1);
        assert_eq!(Schedule::Tree(3).candidates_per_chain(), 7);
        assert_eq!(Schedule::RejectChain(16).candidates_per_chain(), 16);
    }
}
