//! How a render samples: Metropolis chains parallelised the naive way, as a speculative tree
//! of depth d or as a reject chain of length l — or the path tracer — and their names on the
//! command line.

use std::str::FromStr;

use shared::mmlt::{candidates_per_chain, METHOD_REJECT_CHAIN, METHOD_TREE};
use shared::reject_chain::MAX_REJECT_CHAIN;
use shared::tree::MAX_TREE_DEPTH;

/// How a render samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// The path tracer (`pt`): independent samples of every pixel, no chains
    /// (`shared::path_tracer`, the estimator `smlt reference` runs).
    PathTracer,
    /// Speculative tree of depth d (`s<d>`); d = 1 is the naive parallel MMLT (`naive`).
    Tree(u32),
    /// Reject chain of l proposals (`rc<l>`).
    RejectChain(u32),
}

impl Method {
    /// Candidates traced per chain and iteration (1 for the path tracer, which has no chains).
    pub fn candidates_per_chain(&self) -> u32 {
        match *self {
            Method::PathTracer => 1,
            Method::Tree(d) => candidates_per_chain(METHOD_TREE, d, 0),
            Method::RejectChain(l) => candidates_per_chain(METHOD_REJECT_CHAIN, 1, l),
        }
    }
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Method::PathTracer => write!(f, "pt"),
            Method::Tree(1) => write!(f, "naive"),
            Method::Tree(d) => write!(f, "s{d}"),
            Method::RejectChain(l) => write!(f, "rc{l}"),
        }
    }
}

impl FromStr for Method {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        if s == "pt" {
            return Ok(Method::PathTracer);
        }
        if s == "naive" {
            return Ok(Method::Tree(1));
        }
        if let Some(d) = s.strip_prefix('s') {
            return match d.parse::<u32>() {
                Ok(d) if (1..=MAX_TREE_DEPTH).contains(&d) => Ok(Method::Tree(d)),
                _ => Err(format!(
                    "'{s}': the speculative tree depth must be 1..={MAX_TREE_DEPTH} (s1..s{MAX_TREE_DEPTH})"
                )),
            };
        }
        if let Some(l) = s.strip_prefix("rc") {
            return match l.parse::<u32>() {
                Ok(l) if (2..=MAX_REJECT_CHAIN).contains(&l) => Ok(Method::RejectChain(l)),
                _ => Err(format!("'{s}': the reject-chain length must be 2..={MAX_REJECT_CHAIN} (rc2..rc{MAX_REJECT_CHAIN})")),
            };
        }
        Err(format!(
            "'{s}' is not a method: use pt, naive, s<d> with d in 1..={MAX_TREE_DEPTH}, or rc<l> with l in 2..={MAX_REJECT_CHAIN}"
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_and_print() {
        for (name, method, printed) in [
            ("pt", Method::PathTracer, "pt"),
            ("naive", Method::Tree(1), "naive"),
            ("s1", Method::Tree(1), "naive"),
            ("s3", Method::Tree(3), "s3"),
            ("s8", Method::Tree(8), "s8"),
            ("rc2", Method::RejectChain(2), "rc2"),
            ("rc64", Method::RejectChain(64), "rc64"),
        ] {
            let m: Method = name.parse().unwrap();
            assert_eq!(m, method, "{name}");
            assert_eq!(m.to_string(), printed);
        }
        for bad in ["s0", "s9", "rc1", "rc65", "tree", "", "s", "rc", "pt1", "PT"] {
            assert!(bad.parse::<Method>().is_err(), "{bad}");
        }
    }

    #[test]
    fn candidates_per_chain() {
        assert_eq!(Method::PathTracer.candidates_per_chain(), 1);
        assert_eq!(Method::Tree(1).candidates_per_chain(), 1);
        assert_eq!(Method::Tree(3).candidates_per_chain(), 7);
        assert_eq!(Method::RejectChain(16).candidates_per_chain(), 16);
    }
}
