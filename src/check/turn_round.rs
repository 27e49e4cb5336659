//! A job's operation begins (`MoveKind::Operation`, docs/job.md "Operations"): the operator has
//! taken the part out of the jaws, turned it round (or not) and clamped it again. The checker
//! takes the part as it holds it at that instant (`scene::turn_round::the_part`: the piece cut
//! off after a part-off, else the whole stock), maps it where the operation says
//! (`StockTransform`), puts the operation's jaws in the scene, and goes on: every later move
//! meets that part and those jaws. Nothing on the turret moves.

use super::{Checker, Obstacle, OVERTRAVEL_KEY};
use crate::finding::{Finding, Kind, Severity};
use crate::geom::{self, Aabb, P2};
use crate::interp::Move;
use crate::machine::OpTailstock;
use crate::motion::Timed;
use crate::scene::turn_round::{material_extent, max_radius, the_part};
use crate::scene::{DexelStock, Revolved, StockTransform};

impl Checker<'_> {
    /// Operation `i` of the machine's (the job's) operations begins at move `m`.
    pub(super) fn turn_round(&mut self, m: &Move, item: &Timed, i: usize) {
        let Some(op) = self.machine.operations.get(i) else {
            return;
        };
        // Contacts in progress end here: the part they touched is out of the jaws.
        self.episodes.close_except(|k| k == OVERTRAVEL_KEY);
        self.episodes.operation = i as u32 + 2;
        self.turned = true;
        // What the 3D path carried over from the part before (a job refuses operations on a
        // machine with a kinematic tree; a library caller may still build one).
        self.plunge3 = None;
        self.gap3 = None;
        self.mill = None;
        self.scene.chuck = op.chuck.clone().map(|p| Revolved::new("chuck", p));
        match &op.tailstock {
            OpTailstock::AsItStood => {}
            OpTailstock::Out => self.scene.tailstock = None,
            OpTailstock::At { outline, .. } => {
                self.scene.tailstock = Some(Revolved::new("tailstock", outline.clone()));
            }
        }
        // Advanced as the operation begins: the program's state there (an operation's
        // `tailstock.in_use` set it in the interpreter).
        self.tailstock_in = self.now.state.tailstock_advanced;
        let Some(stock) = self.ensure_stock() else {
            return;
        };
        let Some((part, _)) = the_part(stock) else {
            // Nothing left to turn round: no stock from here on.
            self.stock = Some(DexelStock::from_columns(0.0, self.settings.tolerance_mm, Vec::new()));
            self.stock_box = None;
            return;
        };
        let Some((lo, hi)) = material_extent(&part) else { return };
        let t = StockTransform::placing(lo, hi, op.reverse, op.stand);
        let mut turned = t.stock(&part);
        let r = max_radius(&turned);
        let (lo, hi) = material_extent(&turned).unwrap_or((t.z(lo), t.z(hi)));
        self.stock_box = Some(Aabb {
            min: P2::new(-r, lo),
            max: P2::new(r, hi),
        });
        // The jaws must close on the part, not inside it: an overlap is the job's mistake (where
        // the operation says the part stands, or its jaws), reported at the operation's start.
        let hit = self
            .scene
            .chuck
            .as_ref()
            .and_then(|ch| turned.overlap(ch.outline.points(), geom::TOUCH_EPS));
        let held = format!(
            "the part as operation {} holds it (z {} .. {}, Ø{} max)",
            i + 2,
            crate::machine::num(lo),
            crate::machine::num(hi),
            crate::machine::num(2.0 * r)
        );
        if let Some(hit) = hit {
            let message = format!(
                "{}: {held} overlaps its chuck by {:.3} mm: the jaws close on the part's surface, they cannot reach into it; check where the operation says the part stands (`front` or `grip`) and its `chuck.outline`",
                op.origin, hit.depth
            );
            self.job_collision(m, item, i, ["stock", "chuck"], hit.depth, message);
        }
        // The tailstock in use for this operation meets the part as it now stands, and the jaws.
        if let Some(ts) = self.obstacle(Obstacle::Tailstock).cloned() {
            let tip = crate::machine::num(ts.outline.aabb().min.y);
            if let Some(hit) = turned.overlap(ts.outline.points(), geom::TOUCH_EPS) {
                let message = format!(
                    "{}: the tailstock in use (live centre at z {tip}) runs {:.3} mm into {held}: a live centre only meets the part's end face (its centre hole); give the operation's `tailstock.z` where the part's end now is, or `tailstock.in_use = false`",
                    op.origin, hit.depth
                );
                self.job_collision(m, item, i, ["tailstock", "stock"], hit.depth, message);
            }
            let chuck = self
                .scene
                .chuck
                .as_ref()
                .and_then(|ch| geom::overlap(&ts.outline, &ch.outline));
            if let Some(depth) = chuck {
                let message = format!(
                    "{}: the tailstock in use (live centre at z {tip}) overlaps operation {}'s chuck by {depth:.3} mm; check the operation's `tailstock.z` and its `chuck`",
                    op.origin,
                    i + 2
                );
                self.job_collision(m, item, i, ["tailstock", "chuck"], depth, message);
            }
        }
        self.stock = Some(turned);
    }

    /// A collision that the job's operation `i` sets up (its part, jaws and tailstock), at the
    /// operation's line; `message` begins with the operation's place in the job.
    fn job_collision(&mut self, m: &Move, item: &Timed, i: usize, objects: [&str; 2], depth: f64, message: String) {
        let mut f = Finding::at(Kind::Collision, Severity::Error, m.line, 0, message).with_n(m.n);
        f.objects = objects.iter().map(|o| o.to_string()).collect();
        f.depth_mm = Some(depth);
        f.time_s = Some(item.t0);
        f.end_time_s = Some(item.t0);
        f.operation = Some(i as u32 + 2);
        self.episodes.findings.push(f);
    }
}
