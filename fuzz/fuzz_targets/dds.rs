//! Fuzz target `dds`: see `crates/texmap/tests/fuzz_harness/mod.rs` for what it exercises.
#![no_main]

#[path = "../../crates/texmap/tests/fuzz_harness/mod.rs"]
mod fuzz_harness;

libfuzzer_sys::fuzz_target!(|data: &[u8]| fuzz_harness::dds(data));
