//! What a Metropolis chain's state is a sample of: the paper's multiplexed paths
//! (`shared::mmlt`) or the path tracer's whole estimate (`shared::pssmlt`).

use serde::{Deserialize, Serialize};
use shared::params::{ESTIMATOR_MULTIPLEXED, ESTIMATOR_PATH};

/// What a chain's state is a sample of.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Estimator {
    /// Multiplexed MLT (the paper's): one technique of one path depth per sample, the depth part
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_are_the_kernels() {
        assert_eq!(Estimator::Multiplexed.code(), ESTIMATOR_MULTIPLEXED);
        assert_eq!(Estimator::Path.code(), ESTIMATOR_PATH);
        assert_ne!(ESTIMATOR_MULTIPLEXED, ESTIMATOR_PATH);
    }
}
