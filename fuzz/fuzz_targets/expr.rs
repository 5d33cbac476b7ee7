//! The population expression parser on arbitrary text (see `demkit_fuzz::expr`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    demkit_fuzz::expr(data);
});
