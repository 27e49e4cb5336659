//! Pick-off and part-off: the part changing hands between the main spindle and the
//! sub-spindle.
//!
//! The sub-spindle's chuck (the first `chuck` component that a sub-spindle axis carries, see
//! [`Three::sub_chucks`]) clamps and unclamps by the machine's M codes (`sub_chuck_close`,
//! `sub_chuck_open`: Haas M110/M111), which the interpreter records in each move's state.
//!
//! - **Clamping**: when the chuck closes, it holds the bar if the stock reaches past its jaw face
//!   (the chuck's nearest point to the main spindle along `z`) at that moment.
//! - **Tearing the bar**: while it holds the bar and the part-off is not through, a move of a
//!   sub-spindle slide pulls on a bar both chucks hold: a `collision` of the sub chuck with the
//!   stock, reported once per clamp.
//! - **Part-off**: when a cut leaves an empty column between material on both sides (the
//!   dexel stock's [`DexelStock::split_off_beyond`]), the material beyond the groove leaves the
//!   stock. If the sub chuck holds the bar, the piece becomes a component of the tree carried by
//!   that chuck (a revolved outline, posed by the sub-spindle's axes from then on) and every
//!   later move checks the turret, its housing, the tools and the main chuck against it, and it
//!   against the stock. Otherwise it falls (into a part catcher): it is gone.
//! - **Unclamping** drops the pieces the chuck holds.
//!
//! Invariant: a piece leaves the scene only when the chuck that holds it opens; while a piece
//! exists every move takes the 3D path (`Route::Hybrid` or `Route::Space`), so no move passes
//! it unchecked.

use std::sync::Arc;

use super::{carried_by_x, Three, KEY_BASE};
use crate::check::episodes::Contact;
use crate::check::Checker;
use crate::collide3::Shape3;
use crate::finding::Kind;
use crate::interp::{ExtraMove, Move};
use crate::kin::{AxisKind, CompId, Component, Geometry, Poser, Role};
use crate::motion::Timed;
use crate::scene::View;

/// The name of a piece the sub-spindle holds.
pub const PIECE: &str = "part_in_sub_chuck";
/// Most outlines of one severed piece kept as components.
const MAX_PIECE_OUTLINES: usize = 8;
/// Episode key of the tearing finding.
const TEAR_KEY: u64 = KEY_BASE - 32;

/// The sub chuck's state as the checker follows it.
#[derive(Clone, Copy, Debug, Default)]
pub(in crate::check) struct Transfer {
    /// The sub chuck is clamped (as the last move's state said).
    closed: bool,
    /// It clamped on the bar, which no part-off has severed yet.
    holds_bar: bool,
    /// The tearing finding of this clamp was reported.
    torn: bool,
    /// Empty columns of the stock after the last move (a part-off makes more).
    empty: usize,
}

impl Checker<'_> {
    /// Before a move is checked: follow the sub chuck's clamp, and report a pull on the bar.
    pub(in crate::check) fn transfer_before(&mut self, m: &Move, e: Option<&ExtraMove>, item: &Timed) {
        let Some(mut three) = self.three.take() else { return };
        self.transfer_before_with(&mut three, m, e, item);
        self.three = Some(three);
    }

    fn transfer_before_with(&mut self, three: &mut Three, m: &Move, e: Option<&ExtraMove>, item: &Timed) {
        let closed = self.now.state.sub_chuck_closed;
        let Some(&chuck) = three.sub_chucks.first() else { return };
        if closed && !three.transfer.closed {
            let holds = self.bar_in_jaws(three, chuck, m, e, item);
            three.transfer = Transfer {
                closed: true,
                holds_bar: holds,
                torn: false,
                empty: three.transfer.empty,
            };
        } else if !closed && three.transfer.closed {
            three.transfer.closed = false;
            three.transfer.holds_bar = false;
            three.drop_pieces();
        }
        let t = three.transfer;
        if !t.holds_bar || t.torn {
            return;
        }
        let Some(e) = e else { return };
        let pulled = (0..4)
            .filter(|&k| k != 1 && !three.tool_axis[k])
            .filter_map(|k| three.ax_extra[k].map(|a| (k, a)))
            .filter(|&(_, a)| matches!(three.kin.axes[a].kind, AxisKind::Linear { .. }))
            .map(|(k, _)| (e.end[k] - e.start[k]).abs())
            .fold(0.0f64, f64::max);
        // A move shorter than the check's tolerance is no pull: a servo holding its place, or
        // live positions' rounding (a replay's -665.9999999999991 after -666), moves it by less.
        if pulled <= self.settings.tolerance_mm.max(crate::geom::TOUCH_EPS) {
            return;
        }
        three.transfer.torn = true;
        let name = three.kin.components[chuck].name.clone();
        let words = self.words3(&three.kin, chuck);
        let (x, z) = self.frame().to_program(m.start);
        self.episodes.contact(
            TEAR_KEY,
            Contact {
                kind: Kind::Collision,
                objects: [name.clone(), "stock".into()],
                words: Some([words.clone(), "stock".into()]),
                line: m.line,
                n: m.n,
                profile_line: m.profile_line,
                time: item.t0,
                x,
                z,
                depth: None,
                message: format!(
                    "the {words} moves while clamped on a bar the main chuck still holds: the part-off is not through (the bar is torn or the sub-spindle stalls)"
                ),
                snapshot: None,
                snapshot3: None,
            },
        );
        self.episodes.clear(TEAR_KEY);
        // Nothing went into anything: the finding says how far the clamped part moved.
        if let Some(f) = self.episodes.findings.last_mut().filter(|f| f.objects[0] == name) {
            f.moved_mm = Some(pulled);
        }
    }

    /// After a move: a part-off hands the piece beyond the groove to the sub chuck, or drops it.
    pub(in crate::check) fn transfer_after(&mut self, m: &Move, e: Option<&ExtraMove>, item: &Timed) {
        let Some(mut three) = self.three.take() else { return };
        self.transfer_after_with(&mut three, m, e, item);
        self.three = Some(three);
    }

    fn transfer_after_with(&mut self, three: &mut Three, m: &Move, e: Option<&ExtraMove>, item: &Timed) {
        let Some(stock) = self.stock.as_mut() else { return };
        if stock.empty_columns() == three.transfer.empty {
            return;
        }
        let piece = stock.split_off_beyond();
        three.transfer.empty = stock.empty_columns();
        let Some(piece) = piece else { return };
        if !three.transfer.holds_bar {
            // Nothing holds it: it falls (a part catcher takes it).
            return;
        }
        three.transfer.holds_bar = false;
        let Some(&chuck) = three.sub_chucks.first() else { return };
        let mut vals = Vec::new();
        three.values(m, e, item, 1.0, &mut vals);
        let tol = self.settings.tolerance_mm;
        for outline in piece.outlines(1e-9).into_iter().take(MAX_PIECE_OUTLINES) {
            let pts: Vec<crate::geom::P2> = outline.iter().map(|p| crate::geom::P2::new(p[0].abs(), p[1])).collect();
            three.add_piece(chuck, pts, &vals, tol);
        }
    }

    /// Whether the stock reaches past the jaw face of `chuck` (its smallest world `z`) at the
    /// start of the move.
    fn bar_in_jaws(&mut self, three: &Three, chuck: CompId, m: &Move, e: Option<&ExtraMove>, item: &Timed) -> bool {
        let Some(shape) = three.shapes[chuck].as_ref() else {
            return false;
        };
        let mut vals = Vec::new();
        three.values(m, e, item, 0.0, &mut vals);
        let mut poser = Poser::new(&three.kin);
        poser.pose(&three.kin, &vals);
        let pose = poser.world(chuck);
        let b = shape.local_box();
        let mut face = f64::INFINITY;
        for i in 0..8 {
            let p = nalgebra::Point3::new(
                if i & 1 == 0 { b.mins.x } else { b.maxs.x },
                if i & 2 == 0 { b.mins.y } else { b.maxs.y },
                if i & 4 == 0 { b.mins.z } else { b.maxs.z },
            );
            face = face.min((pose * p).z);
        }
        let Some(top) = self.stock_box.map(|b| b.max.y) else {
            return false;
        };
        let Some(stock) = self.ensure_stock() else { return false };
        let Some((j0, j1)) = stock.columns_within(face, top + 1.0) else {
            return false;
        };
        (j0..=j1).any(|j| !stock.column_material(j, View::Now).is_empty())
    }
}

impl Three {
    /// Add a piece held by `chuck`: a revolved outline in world coordinates at the axis values
    /// `vals`, carried by the chuck from then on.
    fn add_piece(&mut self, chuck: CompId, outline: Vec<crate::geom::P2>, vals: &[f64], tol: f64) {
        let geometry = Geometry::Revolved(outline);
        let Some(shape) = Shape3::meshed(&geometry, tol) else {
            return;
        };
        let mut poser = Poser::new(&self.kin);
        poser.pose(&self.kin, vals);
        let mount = poser.world(chuck).inverse();
        let k = Arc::make_mut(&mut self.kin);
        let id = k.components.len();
        let label = format!("part in the {}", crate::kin::words::words(&k.components[chuck], None));
        k.components.push(Component {
            name: PIECE.into(),
            parent: Some(chuck),
            mount,
            axis: None,
            geometry: Some(geometry),
            role: Role::Structure,
            station: None,
            label: Some(label),
        });
        for j in 0..id {
            let main_chuck = k.components[j].role == Role::Chuck && !self.sub_chucks.contains(&j);
            if (carried_by_x(k, j) || main_chuck) && self.shapes[j].is_some() {
                k.never_touch.push((j, id));
            }
        }
        self.shapes.push(Some(shape));
        self.pieces.push(id);
    }

    /// The chuck opened: its pieces leave the scene (they are the tree's last components).
    fn drop_pieces(&mut self) {
        let Some(&first) = self.pieces.first() else { return };
        let k = Arc::make_mut(&mut self.kin);
        k.components.truncate(first);
        k.never_touch.retain(|&(a, b)| a < first && b < first);
        self.shapes.truncate(first);
        self.pieces.clear();
    }
}
