//! The last answers of the pair queries, by their exact inputs.
//!
//! The checker asks some questions twice: a move's last probe of a pair is the next move's
//! first, and a contact's depth sample can fall where a probe already was. The same shapes at
//! the same poses (bit for bit) get the same answer from parry, so a question asked again is
//! answered from this table instead of computed: the answers, and so every report, are the
//! same. A question is keyed by the shapes' ids (unique for the life of the process, never
//! reused: a batch's next file cannot meet an answer about this one's shapes), the poses' bits
//! and the depth threshold's. A program asks again far from the first time (a cycle's passes
//! bring the turret back to where it stood), so the table holds every answer, one table per
//! thread, emptied when it reaches [`MAX_HELD`] (about 200 bytes an answer: at most some 13 MB,
//! and only where a program poses 3D pair queries).

use std::cell::RefCell;
use std::collections::HashMap;
use std::sync::atomic::{AtomicU64, Ordering};

use super::Hit;
use crate::kin::Iso;

/// Most answers held per thread.
pub(super) const MAX_HELD: usize = 1 << 16;

static NEXT_ID: AtomicU64 = AtomicU64::new(1);

/// A new shape's id.
pub(super) fn next_id() -> u64 {
    NEXT_ID.fetch_add(1, Ordering::Relaxed)
}

/// Which query.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(super) enum Query {
    OverlapTouch,
    Distance,
}

/// A question: the query, the shapes' ids, their poses' and the threshold's bits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(super) struct Key {
    query: Query,
    ids: [u64; 2],
    poses: [[u64; 7]; 2],
    eps: u64,
}

fn bits(p: &Iso) -> [u64; 7] {
    let t = p.translation.vector;
    let q = p.rotation.quaternion().coords;
    [t.x, t.y, t.z, q.x, q.y, q.z, q.w].map(f64::to_bits)
}

impl Key {
    pub(super) fn new(query: Query, (a, pa): (u64, &Iso), (b, pb): (u64, &Iso), eps: f64) -> Key {
        Key {
            query,
            ids: [a, b],
            poses: [bits(pa), bits(pb)],
            eps: eps.to_bits(),
        }
    }
}

/// An answer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Answer {
    OverlapTouch(Option<Hit>, bool),
    Distance(f64),
}

thread_local! {
    static TABLE: RefCell<HashMap<Key, Answer>> = RefCell::new(HashMap::new());
}

/// The answer held for `key`, if any.
pub(super) fn held(key: &Key) -> Option<Answer> {
    TABLE.with(|t| t.borrow().get(key).copied())
}

/// The answer to `key`: the one held when it was asked before (and not since emptied), else
/// `compute()`'s, then held.
pub(super) fn answer(key: Key, compute: impl FnOnce() -> Answer) -> Answer {
    if let Some(a) = TABLE.with(|t| t.borrow().get(&key).copied()) {
        return a;
    }
    let a = compute();
    TABLE.with(|t| {
        let mut t = t.borrow_mut();
        if t.len() >= MAX_HELD {
            t.clear();
        }
        t.insert(key, a);
    });
    a
}
