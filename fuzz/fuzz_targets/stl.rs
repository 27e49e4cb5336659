//! STL files: arbitrary bytes never panic the reader, and what it accepts passes its own checks.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(mesh) = latheguard::kin::stl::read_stl(data, "fuzz.stl") {
        assert!(latheguard::kin::stl::check_mesh(&mesh, "fuzz.stl").is_ok());
        assert!(mesh.volume() > 0.0);
    }
});
