//! Maps onto circle domains (the unit disk minus round holes): DEQ, LDEQ and the conformal
//! circle-domain map.

pub mod circle_conformal;
pub mod deq;
pub mod ldeq;
mod refusal;
