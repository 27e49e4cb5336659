//! `latheguard accuracy`: the cost-of-accuracy table.

use super::args::{AccuracyArgs, TableFormat};
use super::{emit, read_capped, shown, Trouble, EXIT_CLEAN, MAX_PROGRAM_BYTES};
use latheguard::accuracy;

pub fn run(a: AccuracyArgs) -> Result<u8, Trouble> {
    if let Some(p) = &a.plot {
        let mut inputs = vec![a.program.as_path()];
        inputs.extend(a.machine.as_deref());
        super::check::refuse_overwrite(p, "--plot", &inputs, &[])?;
    }
    // The machine of -m (or the built-in one) with the program's job: the file beside it,
    // --job and the one-off flags (latheguard.toml is read by check and setup only).
    let machine = super::setup::Planner::new(a.machine.as_deref(), true, &a.job)?
        .resolve(&a.program)?
        .machine;
    let src = read_capped(&a.program, MAX_PROGRAM_BYTES)
        .map_err(|why| format!("{}: cannot read: {why}", shown(&a.program)))?;
    let mut rows = accuracy::run(&src, &machine, a.clearance, a.min_depth, usize::from(a.repeats));
    if a.no_timing {
        for r in &mut rows {
            r.run_ms = 0.0;
        }
    }
    if let Some(p) = &a.plot {
        let title = format!("cost of accuracy: {}", shown(&a.program));
        std::fs::write(p, accuracy::plot_svg(&rows, &title))
            .map_err(|e| format!("{}: cannot write: {}", shown(p), super::plain(&e)))?;
    }
    let text = match a.format {
        TableFormat::Json => {
            let mut s = serde_json::to_string_pretty(&rows).unwrap_or_default();
            s.push('\n');
            s
        }
        TableFormat::Text => format!("{}\n{}", shown(&a.program), accuracy::table(&rows, !a.no_timing)),
    };
    emit(None, &text)?;
    Ok(EXIT_CLEAN)
}
