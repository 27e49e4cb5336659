//! The line reader: bytes → blocks. See the module docs of [`crate::gcode`].

use super::Program;

/// Read a whole program. Never fails; problems become `syntax` findings in [`Program::errors`].
pub fn parse(src: &[u8]) -> Program {
    let lines = crate::source::LineIndex::new(src);
    Program {
        lines,
        ..Program::default()
    }
}
