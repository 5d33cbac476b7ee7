//! The landmark file readers on arbitrary bytes (see `demkit_fuzz::landmarks`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    demkit_fuzz::landmarks(data);
});
