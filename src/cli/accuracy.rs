//! `latheguard accuracy`: the cost-of-accuracy table.

use super::args::{AccuracyArgs, TableFormat};
use super::{emit, load_machine, Trouble, EXIT_CLEAN};
use latheguard::accuracy;

pub fn run(a: AccuracyArgs) -> Result<u8, Trouble> {
    let machine = load_machine(a.machine.as_deref())?;
    let src = std::fs::read(&a.program).map_err(|e| format!("{}: cannot read: {e}", a.program.display()))?;
    let rows = accuracy::run(&src, &machine, a.clearance, a.repeats);
    if let Some(p) = &a.plot {
        let title = format!("cost of accuracy: {}", a.program.display());
        std::fs::write(p, accuracy::plot_svg(&rows, &title))
            .map_err(|e| format!("{}: cannot write: {e}", p.display()))?;
    }
    let text = match a.format {
        TableFormat::Json => {
            let mut s = serde_json::to_string_pretty(&rows).unwrap_or_default();
            s.push('\n');
            s
        }
        TableFormat::Text => format!("{}\n{}", a.program.display(), accuracy::table(&rows)),
    };
    emit(None, &text)?;
    Ok(EXIT_CLEAN)
}
