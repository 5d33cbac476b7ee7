//! The cartogram on the globe (SDEM paper §5.3).

use super::regions::RegionSet;
use super::{Cartogram, Config};
use crate::methods::ProgressFn;
use crate::{Error, Result};

/// Computes the cartogram of `set` (longitude/latitude degrees) on the unit sphere.
pub fn run(_set: &RegionSet, _config: &Config, _path: &str, _p: ProgressFn) -> Result<Cartogram> {
    Err(Error::Argument("--sphere is not available yet".into()))
}
