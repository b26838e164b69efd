//! The types of the association step's shapes round, below its steps:
//! the tuning ([`ShapesOptions`]), what a round reads ([`Domains`],
//! [`Chain`]) and returns ([`ShapesOutcome`]), and what is kept across
//! rounds ([`ShapesState`], with the cache keys of the branches and of the
//! registrations). The steps (sibling files) add their methods to
//! [`ShapesState`]; the driver (`mod.rs`) sits above them.

use crate::ibox::IntervalBox;
use crate::interval::Interval;
#[cfg(not(target_arch = "wasm32"))]
use crate::shapes::branch_memo::BranchMemo;
use crate::shapes::chain_sums::StoredSums;
use crate::shapes::distinct::Distinct;
use crate::shapes::frames::{FrameOptions, Frames};
use crate::shapes::region::Paving;
use crate::shapes::registration::RegisterOptions;
use crate::union_find::Uf;

/// Tuning of the shapes round.
#[derive(Debug, Clone, PartialEq)]
pub struct ShapesOptions {
    /// Most boxes in one region's paving.
    pub max_boxes: usize,
    /// Boxes narrower than this are not bisected further (metres).
    pub resolution: f64,
    /// Most members whose shapes cut the halves of a bisection (the
    /// thinnest ones).
    pub refine_shapes: usize,
    /// Node budget of the exact witness search.
    pub node_budget: usize,
    /// Detections after each one (in step order) tried for a relative
    /// distinct pair.
    pub max_ahead: usize,
    /// Node budget of each pass of the clique rule.
    pub clique_budget: usize,
    /// Local frames ([`crate::shapes::frames`]).
    pub frames: FrameOptions,
    /// Most frame/inference passes in one round.
    pub frame_passes: usize,
    /// Whether the local frames are registered on the witness regions.
    pub registration: bool,
    /// Steps around a registration step whose pieces are used.
    pub register_gap: usize,
    /// Least steps between two registration steps.
    pub register_every: usize,
    /// Most groups in one registration.
    pub register_groups: usize,
    /// A registration step is done again when its position box or a
    /// witness region shrank by more than this fraction of its width since
    /// the last time (or the groups around it changed).
    pub register_slack: f64,
    /// Tuning of each registration.
    pub register: RegisterOptions,
    /// Threads for the independent work of a round ([`crate::par::map`]:
    /// the registrations, the local frames' pieces and their tests); the
    /// same bits for any count.
    pub threads: usize,
}

impl Default for ShapesOptions {
    fn default() -> Self {
        ShapesOptions {
            max_boxes: 64,
            resolution: 0.0,
            refine_shapes: 16,
            node_budget: 20_000,
            max_ahead: 64,
            clique_budget: 200_000,
            frames: FrameOptions::default(),
            frame_passes: 3,
            registration: true,
            register_gap: 300,
            register_every: 50,
            register_groups: 8,
            register_slack: 0.02,
            register: RegisterOptions::default(),
            threads: 1,
        }
    }
}

/// Pieces moved to a registration step and coarsened: by (step, piece
/// id), the displacement sum that moved them and the coarsened boxes.
pub(super) type CoarsePieces =
    std::collections::BTreeMap<(usize, u64), (Vec<Interval>, Vec<IntervalBox>)>;

/// A member's position box, detection box, its region's hull and box count.
pub(super) type BranchKey = (IntervalBox, IntervalBox, IntervalBox, usize);

/// The domains a round reads and contracts.
#[derive(Debug)]
pub struct Domains<'a> {
    /// Dimension of positions (2 or 3).
    pub dim: usize,
    /// Position domains, (N+1)·dim, step-major.
    pub pos: &'a mut [Interval],
    /// Detection variables d(j).
    pub det: &'a mut [IntervalBox],
    /// Heading (or yaw) at each detection's step.
    pub heading_at: &'a [Interval],
    /// Displacement boxes D(i), N·dim, step-major.
    pub disp: &'a [Interval],
}

/// The motion chain as a round sees it (the propagator implements it).
pub trait Chain {
    /// Sweeps the change of p(`from`) forward to p(`to`) (`from < to`),
    /// while it moves a bound by more than the tolerance; returns whether
    /// it is still alive at `to`. Err: a position emptied (the reason).
    fn sweep_forward(
        &mut self,
        pos: &mut [Interval],
        from: usize,
        to: usize,
    ) -> Result<bool, String>;
    /// p(`step`) changed (a detection step): the caller sweeps it along
    /// the chain, both ways, later.
    fn changed(&mut self, step: usize);
}

/// What a round did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ShapesOutcome {
    /// Pairs of detections proved to see the same landmark.
    pub unions: Vec<(usize, usize)>,
    /// Whether a bound moved by more than the tolerance or a group grew.
    pub moved: bool,
    /// Detections whose boxes (or whose p(step)) moved by more than the
    /// tolerance, or that joined a group.
    pub moved_detections: Vec<usize>,
    /// Contractor calls (pieces contracted).
    pub contractions: u64,
    /// Why the mission is infeasible, when it was proved.
    pub infeasible: Option<String>,
}

/// State kept across rounds: the regions of the groups and the last
/// witnesses.
#[derive(Debug, Clone, Default)]
pub struct ShapesState {
    /// Tuning.
    pub options: ShapesOptions,
    /// Region of each group, stored at one member (the root).
    pub(super) regions: Vec<Option<Paving>>,
    /// The centre box with which each detection last cut its group's
    /// region (`None`: never).
    pub(super) cut_with: Vec<Option<IntervalBox>>,
    /// What each group member's last branch against its region read: its
    /// position box, its detection box, the region's hull and box count
    /// (the branch is skipped while they stay the same: it would give the
    /// same pieces).
    pub(super) branched: Vec<Option<BranchKey>>,
    /// One detection of each of the last witnesses.
    pub(super) witnesses: Vec<usize>,
    /// Detection pairs proved distinct.
    pub(super) distinct: Distinct,
    /// Group regions in local frames.
    pub(super) frames: Frames,
    /// Whether the relative pairs were computed (once: they rest on the
    /// displacement boxes and the measurements, which do not change).
    pub(super) relative_done: bool,
    /// What each registration step last read, and the candidates it gave.
    /// By step, in step order.
    pub(super) registered: Vec<(usize, RegKey, Vec<u64>)>,
    /// The pieces the last round's registrations moved and coarsened
    /// (the same inputs give the same boxes, so they are read
    /// from here while the piece and its displacement sum are the same).
    pub(super) coarse_pieces: CoarsePieces,
    /// The displacement boxes D(i) stay the same over the propagation
    /// (the caller's promise: every model but odometry2d, whose D(i)
    /// follow the headings): the chain sums are then built once
    /// ([`ShapesState::stored_sums`]) instead of each round.
    pub fixed_displacements: bool,
    /// The chain sums of the last round, with `fixed_displacements`.
    pub(super) stored_sums: Option<StoredSums>,
    /// Every step runs in every round over every group (the schedule
    /// before the incremental one; kept as the reference the tests compare with):
    /// no group skipped for not having moved, the distinct pairs of the
    /// detection shapes computed even when the operator named every
    /// detection's landmark.
    pub full_work: bool,
    /// Per group (at its first member): the bits of what its step 1 read
    /// when it last ran ([`ShapesState::group_signature`]); the step is
    /// skipped for the group while they stay the same.
    pub(super) group_seen: Vec<Option<Vec<u64>>>,
    /// The distinct pairs between different groups were not looked for
    /// this round (the relative pairs of round 1, the frames' tests): the
    /// groups number at most n, so they could serve the witness search
    /// alone ([`ShapesState::distinct_pairs`]); it looks for them when it
    /// finds fewer than n witnesses without them.
    pub(super) cross_deferred: CrossDeferred,
    /// Natively: per detection, what its last branch against the witness
    /// regions read and found ([`crate::shapes::branch_memo`]).
    #[cfg(not(target_arch = "wasm32"))]
    pub(super) branch_memos: Vec<BranchMemo>,
    /// Natively: the witness regions' versions between rounds.
    #[cfg(not(target_arch = "wasm32"))]
    pub(super) region_versions: RegionVersions,
}

/// What the distinct pairs between different groups left undone in a
/// round (see [`ShapesState::cross_deferred`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct CrossDeferred {
    /// The relative pairs between different groups (round 1's).
    pub relative: bool,
    /// The frames' tests (this round's).
    pub frames: bool,
}

/// The inputs of one registration (see [`RegKey::close`]).
#[derive(Debug, Clone)]
pub(super) struct RegKey {
    pub p: IntervalBox,
    pub roots: Vec<usize>,
    /// A detection of each witness slot's group.
    pub slots: Vec<usize>,
    pub fixed: Vec<Option<usize>>,
    pub pieces: usize,
    pub witnesses: Vec<IntervalBox>,
}

impl RegKey {
    /// Whether a registration that read `self` can stand for one reading
    /// `new`: the same groups and pieces, each witness slot holding the
    /// same landmark (its witness in one group of `uf` with the old one's:
    /// the candidate masks name witnesses by slot, so a mask is only
    /// carried over while slot i is the same landmark in both rounds), and
    /// the position box and the witness regions' hulls shrunk by at most
    /// the fraction `slack` of their widths on every axis since. Its answer
    /// holds (it was sound for larger boxes, and says which landmarks the
    /// groups may see); a registration on the smaller boxes could only be
    /// tighter, by little.
    pub fn close(&self, new: &RegKey, slack: f64, uf: &mut Uf) -> bool {
        let near = |a: &IntervalBox, b: &IntervalBox| {
            a.dim() == b.dim()
                && (0..a.dim()).all(|x| {
                    let (wa, wb) = (a[x].width(), b[x].width());
                    wb >= wa * (1.0 - slack) && b[x].is_subset(a[x])
                })
        };
        self.roots == new.roots
            && self.slots.len() == new.slots.len()
            && self
                .slots
                .iter()
                .zip(&new.slots)
                .all(|(&a, &b)| uf.find(a) == uf.find(b))
            && self.fixed == new.fixed
            && self.pieces == new.pieces
            && self.witnesses.len() == new.witnesses.len()
            && near(&self.p, &new.p)
            && self
                .witnesses
                .iter()
                .zip(&new.witnesses)
                .all(|(a, b)| near(a, b))
    }
}

impl ShapesState {
    /// A state for `k` detections.
    pub fn new(k: usize) -> ShapesState {
        ShapesState {
            options: ShapesOptions::default(),
            regions: vec![None; k],
            cut_with: vec![None; k],
            branched: vec![None; k],
            witnesses: Vec::new(),
            distinct: Distinct::default(),
            frames: Frames::default(),
            relative_done: false,
            registered: Vec::new(),
            coarse_pieces: CoarsePieces::new(),
            fixed_displacements: false,
            stored_sums: None,
            full_work: false,
            group_seen: vec![None; k],
            cross_deferred: CrossDeferred::default(),
            #[cfg(not(target_arch = "wasm32"))]
            branch_memos: vec![BranchMemo::default(); k],
            #[cfg(not(target_arch = "wasm32"))]
            region_versions: RegionVersions::default(),
        }
    }

    /// The region of a group (any member may hold it), when one was built.
    pub fn region_of(&self, group: &[usize]) -> Option<&Paving> {
        group.iter().find_map(|&j| self.regions.get(j)?.as_ref())
    }
}

/// The versions of the witness regions' contents, for the branches' memos
/// ([`crate::shapes::branch_memo`]): a version names one content of a
/// region (its boxes, bit for bit). A slot's region changes only through
/// `Witnesses::region_mut`, which gives it a new version first; at the
/// round's start a region whose boxes have the bits of a region at the
/// last round's end takes that region's version, any other a new one.
/// Versions are never given twice to different contents (the counter only
/// grows), so a memo can only be reused on the very boxes it read.
#[cfg(not(target_arch = "wasm32"))]
#[derive(Debug, Clone, Default)]
pub(super) struct RegionVersions {
    /// Per slot, the version of its region's boxes.
    pub slot: Vec<u64>,
    /// The last version given.
    pub(super) last: u64,
    /// The bits of the regions at the last round's end, with their
    /// versions.
    seen: Vec<(Vec<u64>, u64)>,
}

#[cfg(not(target_arch = "wasm32"))]
impl RegionVersions {
    fn bits(p: &Paving) -> Vec<u64> {
        let mut out = vec![p.boxes().len() as u64];
        for b in p.boxes() {
            for x in b.axes() {
                out.push(x.lo().to_bits());
                out.push(x.hi().to_bits());
            }
        }
        out
    }

    /// The versions of a round's witness regions, as they are taken.
    pub(super) fn start(&mut self, regions: &[Paving]) {
        self.slot = regions
            .iter()
            .map(|p| {
                let b = Self::bits(p);
                match self.seen.iter().find(|e| e.0 == b) {
                    Some(e) => e.1,
                    None => {
                        self.last += 1;
                        self.last
                    }
                }
            })
            .collect();
    }

    /// The regions as the round leaves them.
    pub(super) fn end(&mut self, regions: &[Paving]) {
        self.seen = regions
            .iter()
            .zip(&self.slot)
            .map(|(p, &v)| (Self::bits(p), v))
            .collect();
    }
}
