#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| hydrolux_core::fuzz::obj(data));
