//! The STL reader on arbitrary bytes.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    demkit_fuzz::mesh(data, demkit_fuzz::MeshFormat::Stl);
});
