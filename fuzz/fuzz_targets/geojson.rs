//! The GeoJSON regions reader on arbitrary text (see `demkit_fuzz::geojson`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    demkit_fuzz::geojson(data);
});
