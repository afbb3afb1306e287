//! Random evaluation: the chaos game on a (graph-directed) IFS.
//!
//! The walk goes *backwards* along arrows: a point `λ` of the attractor of
//! state `Y` gives the point `M λ` of the attractor of `X` for every arrow
//! `X → Y` (DESIGN §1), so from `Y` the walk picks an incoming arrow with its
//! probability, moves `λ` and the state, and emits `P λ` whenever it is at
//! the root. Default probabilities are proportional to `|det M|` (the
//! projected map's area ratio: the Bézier-fractal contours paper §2.2; on more control points than
//! the dimension plus one, see [`det_weights`]), with a floor so that
//! singular maps (the fern's stem) are still visited. When the automaton is
//! not strongly connected the walk restarts now and then in a random state
//! from the last point it had there, so every state keeps feeding the root.

use rayon::prelude::*;

use super::pieces::pieces;
use super::plan::Plan;
use super::sampling::{Alias, RandomSettings, Rng, check_samples, det_weights};
use super::settings::EvalError;
use crate::automaton::{ArrowKind, Automaton};
use crate::design::Model;
use crate::geometry::{PlainIfs, Shape};

struct Incoming {
    /// Per state: source states, matrices (row-major n_src × n_state), alias table.
    arrows: Vec<Vec<(usize, Vec<f64>)>>,
    alias: Vec<Option<Alias>>,
    /// Per state, per incoming arrow: `s · c_arrow` (the colour step's constant term).
    colour: Vec<Vec<f64>>,
    /// Per state, per incoming arrow: its name and its probability (normalised).
    chosen: Vec<Vec<(String, f64)>>,
}

/// A chaos game prepared for an automaton and model: probabilities, alias
/// tables and the incoming arrows of every state.
pub struct ChaosGame {
    plan: Plan,
    pieces: super::pieces::Pieces,
    inc: Incoming,
    root: usize,
    single: bool,
    pool: rayon::ThreadPool,
    settings: RandomSettings,
}

/// Checks the colours and probabilities the settings give: each names a
/// subdivision arrow (`arrows`; probabilities one that is walked, `walked`)
/// and is in range.
fn check_choices(settings: &RandomSettings, arrows: &[&str], walked: &[&str]) -> Result<(), EvalError> {
    let unknown = |name: &str, among: &[&str], what: &str| {
        let help = crate::names::suggest(name, among.iter().copied())
            .map(|h| format!(" (did you mean `{h}`?)"))
            .unwrap_or_default();
        EvalError::Probability(format!("no subdivision arrow named `{name}` to {what}{help}"))
    };
    for (name, c) in &settings.colours {
        if !arrows.contains(&name.as_str()) {
            return Err(unknown(name, arrows, "colour"));
        }
        if !(0.0..=1.0).contains(c) {
            return Err(EvalError::Probability(format!(
                "the colour of `{name}` is {c}: colour coordinates are between 0 and 1"
            )));
        }
    }
    for (name, p) in &settings.probabilities {
        if !walked.contains(&name.as_str()) {
            return Err(unknown(name, walked, "give a probability"));
        }
        if !p.is_finite() || *p < 0.0 {
            return Err(EvalError::Probability(format!(
                "the probability of `{name}` is {p}: probabilities are finite and at least 0"
            )));
        }
    }
    Ok(())
}

/// The probabilities of the arrows `names` (matrices `mats`) into the
/// state `state`: as the settings give them, ∝ |det| otherwise; uniform
/// when all are 0 by default.
fn probabilities(
    mats: &[&nalgebra::DMatrix<f64>],
    names: &[&str],
    dim: usize,
    settings: &RandomSettings,
    state: &str,
) -> Result<Vec<f64>, EvalError> {
    let given = |n: &str| settings.probabilities.iter().find(|(a, _)| a == n).map(|(_, p)| *p);
    let mut w = det_weights(mats, dim);
    for (k, n) in names.iter().enumerate() {
        if let Some(p) = given(n) {
            w[k] = p;
        }
    }
    if w.iter().sum::<f64>() <= 0.0 {
        if names.iter().any(|n| given(n).is_some()) {
            return Err(EvalError::Probability(format!(
                "the arrows into `{state}` all have probability 0: the walk could not go on"
            )));
        }
        w = vec![1.0; w.len()];
    }
    Ok(w)
}

impl Incoming {
    /// Keeps the states the roots' attractors are made of: reachable from
    /// them along subdivision arrows (`A_X = ∪ M · A_Y` over X → Y); the
    /// others are left out. Which states are kept.
    fn keep_feeding(&mut self, roots: &[usize]) -> Vec<bool> {
        let size = self.arrows.len();
        let mut feeding = vec![false; size];
        let mut stack = roots.to_vec();
        for &r in roots {
            feeding[r] = true;
        }
        while let Some(s) = stack.pop() {
            let targets: Vec<usize> =
                (0..size).filter(|&t| !feeding[t] && self.arrows[t].iter().any(|(src, _)| *src == s)).collect();
            for t in targets {
                feeding[t] = true;
                stack.push(t);
            }
        }
        for (s, keep) in feeding.iter().enumerate() {
            if !keep {
                self.arrows[s].clear();
                self.colour[s].clear();
                self.chosen[s].clear();
                self.alias[s] = None;
            }
        }
        feeding
    }
}

impl ChaosGame {
    /// Prepares the walk.
    ///
    /// # Errors
    /// A non-stochastic or non-contractive automaton, a model that does not
    /// fit, an unknown arrow in the probabilities, or a root no arrow leads into.
    pub fn new(automaton: &Automaton<f64>, model: &Model, settings: &RandomSettings) -> Result<ChaosGame, EvalError> {
        check_samples(settings.points)?;
        let plan = Plan::new(automaton, &[])?;
        super::prepared::convergence_warnings(automaton, settings.force)?;
        let pieces = pieces(automaton, model)?;
        let bytes = (settings.points as u128).saturating_mul(pieces.dim as u128 * 8);
        if bytes > settings.memory_limit as u128 {
            return Err(EvalError::TooLarge { estimate: bytes, limit: settings.memory_limit });
        }
        let size = plan.states.len();
        let mut inc = Incoming {
            arrows: vec![Vec::new(); size],
            alias: vec![None; size],
            colour: vec![Vec::new(); size],
            chosen: vec![Vec::new(); size],
        };
        let mut mats: Vec<Vec<&nalgebra::DMatrix<f64>>> = vec![Vec::new(); size];
        let mut names: Vec<Vec<&str>> = vec![Vec::new(); size];
        let subdivision: Vec<_> = automaton.arrows().filter(|(_, a)| a.kind == ArrowKind::Subdivision).collect();
        if let Some(name) = settings.dropped.iter().find(|n| !subdivision.iter().any(|(_, a)| a.name == **n)) {
            return Err(EvalError::UnknownArrow(name.clone()));
        }
        let speed = settings.colour_speed;
        if !(0.0..=1.0).contains(&speed) {
            return Err(EvalError::Probability(format!("the colour speed is {speed}: it is between 0 and 1")));
        }
        for (k, (id, arrow)) in subdivision.iter().enumerate() {
            if settings.dropped.contains(&arrow.name) {
                // Not walked; the others keep their colours.
                continue;
            }
            let (from, to) = automaton.arrow_ends(*id);
            let m = &arrow.matrix;
            let row_major = (0..m.nrows()).flat_map(|i| (0..m.ncols()).map(move |j| m[(i, j)])).collect();
            inc.arrows[to.index()].push((from.index(), row_major));
            mats[to.index()].push(m);
            names[to.index()].push(&arrow.name);
            let c = super::sampling::arrow_colour(settings, k, subdivision.len(), &arrow.name);
            inc.colour[to.index()].push(speed * c);
        }
        let walked: Vec<&str> = names.iter().flatten().copied().collect();
        check_choices(settings, &subdivision.iter().map(|(_, a)| a.name.as_str()).collect::<Vec<_>>(), &walked)?;
        for s in 0..size {
            if !mats[s].is_empty() {
                let name = &plan.state(s).name;
                let p = probabilities(&mats[s], &names[s], pieces.dim, settings, name)?;
                let total: f64 = p.iter().sum();
                inc.chosen[s] = names[s].iter().zip(&p).map(|(n, w)| (n.to_string(), w / total)).collect();
                inc.alias[s] = Some(Alias::new(&p));
            }
        }
        let root = pieces.pieces[0].state;
        let mut roots: Vec<usize> = pieces.pieces.iter().map(|p| p.state).collect();
        roots.sort_unstable();
        roots.dedup();
        if let Some(&r) = roots.iter().find(|&&r| inc.arrows[r].is_empty()) {
            return Err(EvalError::Unsupported(format!(
                "no subdivision arrow leads into the root `{}`",
                plan.state(r).name
            )));
        }
        let feeding = inc.keep_feeding(&roots);
        let single =
            inc.arrows[root].iter().all(|(src, _)| *src == root) && feeding.iter().filter(|f| **f).count() == 1;
        let threads = settings.threads.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|e| std::io::Error::other(e.to_string()))?;
        Ok(ChaosGame { plan, pieces, inc, root, single, pool, settings: settings.clone() })
    }

    /// The walk as a plain IFS of the plane, what a `.flame` file holds:
    /// the root's maps in modelling coordinates (`P̂ M P̂⁻¹`), their
    /// probabilities and colours.
    ///
    /// # Errors
    /// Why it is not one: a graph-directed automaton (more than one state
    /// walked, or several pieces), a 3D model, or control points that do
    /// not make the maps affine (more than three).
    pub fn plain_ifs(&self) -> Result<PlainIfs, String> {
        if !self.single || self.pieces.pieces.len() != 1 {
            return Err(format!(
                "a .flame file holds one IFS; this automaton is graph-directed (its root `{}` is made of other states' attractors)",
                self.plan.state(self.root).name
            ));
        }
        if self.pieces.dim != 2 {
            return Err("a .flame file holds an IFS of the plane; this model is 3D".into());
        }
        let Some(maps) = self.affine_maps() else {
            return Err(format!(
                "a .flame file holds affine maps; the root `{}` has {} control points, not three in general position, so its maps are not affine in the plane",
                self.plan.state(self.root).name,
                self.plan.state(self.root).dim
            ));
        };
        let speed = self.settings.colour_speed;
        let colours = self.inc.colour[self.root].iter().map(|c| if speed > 0.0 { c / speed } else { 0.0 }).collect();
        let chosen = &self.inc.chosen[self.root];
        Ok(PlainIfs {
            names: chosen.iter().map(|(n, _)| n.clone()).collect(),
            maps: maps.iter().map(|m| [m[0], m[1], m[2], m[3], m[4], m[5]]).collect(),
            probabilities: chosen.iter().map(|(_, p)| *p).collect(),
            colours,
            colour_speed: speed,
        })
    }

    /// Coordinates per point.
    pub fn dim(&self) -> usize {
        self.pieces.dim
    }

    /// Chain number `k` of the seed: `n` points after its burn-in, handed
    /// to `emit` in chunks of at most [`CHUNK`] points (`d` coordinates
    /// each) with their colour coordinates when `COLOUR` (else no colours).
    fn chain<const COLOUR: bool>(&self, k: u64, n: usize, emit: &mut dyn FnMut(&[f64], &[f32])) {
        let mut rng = Rng::new(self.settings.seed.wrapping_mul(0x2545_F491_4F6C_DD1D).wrapping_add(k));
        if self.single && self.pieces.pieces.len() == 1 && self.affine_chain::<COLOUR>(&mut rng, n, emit) {
            return;
        }
        self.general_chain::<COLOUR>(&mut rng, n, emit);
    }

    /// Chain `k`'s points into `slot` (`slot.len() / d` of them).
    fn chain_into(&self, k: u64, slot: &mut [f64]) {
        let mut at = 0;
        self.chain::<false>(k, slot.len() / self.pieces.dim, &mut |xs, _| {
            slot[at..at + xs.len()].copy_from_slice(xs);
            at += xs.len();
        });
    }

    /// Whether the settings' cancel flag is set: the walks stop at their next chunk.
    fn cancelled(&self) -> bool {
        self.settings.cancel.as_ref().is_some_and(crate::progress::Cancel::is_cancelled)
    }

    /// Runs the walk, filling `out` (resized to `points · d`, reusing its allocation).
    pub fn run_into(&self, out: &mut Vec<f64>) {
        let d = self.pieces.dim;
        let s = &self.settings;
        out.resize(s.points * d, 0.0);
        let chains = s.chains.max(1).min(s.points.max(1));
        let per = s.points.div_ceil(chains).max(1);
        let chain = |(k, slot): (usize, &mut [f64])| self.chain_into(k as u64, slot);
        if self.pool.current_num_threads() == 1 {
            out.chunks_mut(per * d).enumerate().for_each(chain);
        } else {
            self.pool.install(|| out.par_chunks_mut(per * d).enumerate().for_each(chain));
        }
    }
}

/// What takes the streamed chains: points, and their colour coordinates (or none).
type ChunkWriter<'a, E> = dyn FnMut(&[f64], &[f32]) -> Result<(), E> + 'a;

use crate::geometry::{BATCH, CHUNK};

impl crate::geometry::PointBatches for ChaosGame {
    fn dim(&self) -> usize {
        ChaosGame::dim(self)
    }

    /// Folds `points` points of the walk without holding them: chains of
    /// [`BATCH`] points (chain `k` seeded by the seed and `k`, so the points
    /// do not depend on the threads) are handed to `visit` in chunks of at
    /// most [`CHUNK`] points, `d` coordinates each, with their colour
    /// coordinates in `[0, 1]` when `colour` (else an empty slice), into one
    /// accumulator per thread made by `init`; the accumulators are merged
    /// by `merge` (which must not depend on the order, like a sum of
    /// counts). Memory: a chunk and an accumulator per thread.
    fn fold<T: Send>(
        &self,
        points: usize,
        colour: bool,
        init: impl Fn() -> T + Sync + Send,
        visit: impl Fn(&mut T, &[f64], &[f32]) + Sync + Send,
        merge: impl Fn(T, T) -> T + Sync + Send,
    ) -> T {
        let batches = points.div_ceil(BATCH);
        // Chains after the ones `run_into` uses.
        let first = self.settings.chains.max(1) as u64;
        // One accumulator per thread; the threads take the next batch as they finish one.
        let next = std::sync::atomic::AtomicUsize::new(0);
        // Batches done, counted and reported under one lock: reports never go backwards.
        let done = std::sync::Mutex::new(0u64);
        let partial = self.pool.broadcast(|_| {
            let mut acc = init();
            loop {
                let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                if k >= batches || self.cancelled() {
                    return acc;
                }
                let n = BATCH.min(points - k * BATCH);
                let mut emit = |xs: &[f64], cs: &[f32]| visit(&mut acc, xs, cs);
                if colour {
                    self.chain::<true>(first + k as u64, n, &mut emit);
                } else {
                    self.chain::<false>(first + k as u64, n, &mut emit);
                }
                if let Some(p) = &self.settings.progress
                    && let Ok(mut done) = done.lock()
                {
                    *done += 1;
                    p.report(*done, batches as u64);
                }
            }
        });
        partial.into_iter().reduce(merge).unwrap_or_else(init)
    }
}

impl ChaosGame {
    /// The chains of `points` points in order, chain by chain (the points of
    /// [`PointBatches::fold`](crate::geometry::PointBatches::fold)), handed to `write` in chunks; chains are made in
    /// parallel a few at a time, so memory is a few chains whatever `points`.
    ///
    /// # Errors
    /// The first error of `write`, which stops the walk.
    pub fn stream<E: Send>(&self, points: usize, mut write: impl FnMut(&[f64]) -> Result<(), E>) -> Result<(), E> {
        self.stream_chains::<false, E>(points, &mut |xs, _| write(xs))
    }

    /// The chains of [`ChaosGame::stream`], with their colour coordinates when `COLOUR`.
    fn stream_chains<const COLOUR: bool, E: Send>(
        &self,
        points: usize,
        write: &mut ChunkWriter<'_, E>,
    ) -> Result<(), E> {
        let first = self.settings.chains.max(1) as u64;
        let batches = points.div_ceil(BATCH);
        let group = self.pool.current_num_threads().max(1) * 2;
        let mut bufs: Vec<(Vec<f64>, Vec<f32>)> = vec![(Vec::new(), Vec::new()); group];
        for start in (0..batches).step_by(group) {
            let ks: Vec<usize> = (start..batches.min(start + group)).collect();
            self.pool.install(|| {
                bufs.par_iter_mut().zip(ks.par_iter()).for_each(|((xs, cs), &k)| {
                    xs.clear();
                    cs.clear();
                    self.chain::<COLOUR>(first + k as u64, BATCH.min(points - k * BATCH), &mut |x, c| {
                        xs.extend_from_slice(x);
                        cs.extend_from_slice(c);
                    });
                })
            });
            for (xs, cs) in &bufs[..ks.len()] {
                write(xs, cs)?;
            }
            if let Some(p) = &self.settings.progress {
                p.report((start + ks.len()) as u64, batches as u64);
            }
        }
        Ok(())
    }
}

impl ChaosGame {
    /// As [`ChaosGame::stream`], with each point's colour coordinate in
    /// `[0, 1]` (the arrows' colours mixed along the walk, as the density
    /// pictures colour by them): `write(points, colours)`.
    ///
    /// # Errors
    /// The first error of `write`, which stops the walk.
    pub fn stream_coloured<E: Send>(
        &self,
        points: usize,
        mut write: impl FnMut(&[f64], &[f32]) -> Result<(), E>,
    ) -> Result<(), E> {
        self.stream_chains::<true, E>(points, &mut write)
    }
}

/// Runs the chaos game and returns the points (a point cloud shape).
///
/// # Errors
/// See [`ChaosGame::new`].
pub fn chaos_game(automaton: &Automaton<f64>, model: &Model, settings: &RandomSettings) -> Result<Shape, EvalError> {
    let game = ChaosGame::new(automaton, model, settings)?;
    let mut out = Vec::new();
    game.run_into(&mut out);
    if game.cancelled() {
        return Err(EvalError::Cancelled);
    }
    // The points moved into the shape, not copied (a copy of a billion coordinates is not cancellable).
    let (dim, count) = (game.dim(), out.len() / game.dim().max(1));
    let object = crate::geometry::Object { name: "chaos game".into(), vertices: 0..count, ..Default::default() };
    Ok(Shape { dim, positions: out, objects: vec![object], ..Shape::default() })
}

impl ChaosGame {
    /// Single-state IFS with `n = d + 1` and affinely independent control points:
    /// iterate the projected affine maps `x ← A x + t` in modelling space.
    /// `false` when the control points do not allow it (then the general walk runs).
    fn affine_chain<const COLOUR: bool>(
        &self,
        rng: &mut Rng,
        total: usize,
        emit: &mut dyn FnMut(&[f64], &[f32]),
    ) -> bool {
        let Some(maps) = self.affine_maps() else { return false };
        let Some(alias) = self.inc.alias[self.root].as_ref() else { return false };
        if self.pieces.dim == 2 {
            self.plane_chain::<COLOUR>(&maps, alias, rng, total, emit);
        } else {
            self.space_chain::<COLOUR>(&maps, alias, rng, total, emit);
        }
        true
    }

    /// The root's arrows as affine maps of space, `d` rows of `[A t]` each
    /// (row-major, `n = d + 1` columns): `P̂ M P̂⁻¹` with `P̂ = [P; 1 … 1]`;
    /// `None` unless the root has `d + 1` well-conditioned control points.
    fn affine_maps(&self) -> Option<Vec<Vec<f64>>> {
        let root = self.root;
        let (control, d, n) = (&self.pieces.pieces[0].control, self.pieces.dim, self.plan.state(root).dim);
        if n != d + 1 {
            return None;
        }
        let mut ph = nalgebra::DMatrix::<f64>::zeros(n, n);
        for a in 0..d {
            for i in 0..n {
                ph[(a, i)] = control[a * n + i];
            }
        }
        for i in 0..n {
            ph[(d, i)] = 1.0;
        }
        let inv = ph.clone().try_inverse()?;
        if ph.norm() * inv.norm() > 1e8 {
            return None;
        }
        let maps = self.inc.arrows[root].iter().map(|(_, m)| {
            let h = &ph * nalgebra::DMatrix::from_row_slice(n, n, m) * &inv;
            (0..d).flat_map(|a| (0..n).map(move |j| (a, j))).map(|(a, j)| h[(a, j)]).collect()
        });
        Some(maps.collect())
    }

    /// The affine chain in the plane: two walks interleaved (their points
    /// alternate), so that the steps of one overlap the other's, each a
    /// chain of dependent multiplications.
    fn plane_chain<const COLOUR: bool>(
        &self,
        maps: &[Vec<f64>],
        alias: &Alias,
        rng: &mut Rng,
        total: usize,
        emit: &mut dyn FnMut(&[f64], &[f32]),
    ) {
        let (keep, tint) = (1.0 - self.settings.colour_speed, &self.inc.colour[self.root]);
        let maps: Vec<[f64; 7]> =
            maps.iter().zip(tint).map(|(m, t)| [m[0], m[1], m[2], m[3], m[4], m[5], *t]).collect();
        let mut xs = [0.0; CHUNK * 4];
        let mut cs = [0f32; CHUNK];
        let mut at = [[0.0, 0.0, 0.5]; 2];
        let mut settle = 2 * self.settings.burn_in;
        while settle > 0 {
            let here = settle.min(CHUNK);
            at = walk_plane::<COLOUR>(&maps, alias, rng, keep, at, &mut xs[..2 * here], &mut cs[..here]);
            settle -= here;
        }
        let mut left = total;
        while left > 0 && !self.cancelled() {
            let here = left.min(CHUNK);
            at = walk_plane::<COLOUR>(&maps, alias, rng, keep, at, &mut xs[..2 * here], &mut cs[..here]);
            emit(&xs[..2 * here], if COLOUR { &cs[..here] } else { &[] });
            left -= here;
        }
    }

    /// The affine chain in `d ≠ 2` dimensions.
    fn space_chain<const COLOUR: bool>(
        &self,
        maps: &[Vec<f64>],
        alias: &Alias,
        rng: &mut Rng,
        total: usize,
        emit: &mut dyn FnMut(&[f64], &[f32]),
    ) {
        let (keep, tint) = (1.0 - self.settings.colour_speed, &self.inc.colour[self.root]);
        let (d, n) = (self.pieces.dim, self.pieces.dim + 1);
        let mut xs = [0.0; CHUNK * 4];
        let mut cs = [0f32; CHUNK];
        let mut c = 0.5;
        let mut x = vec![0.0; d];
        let mut next = vec![0.0; d];
        let mut step = |x: &mut Vec<f64>, rng: &mut Rng| {
            let i = alias.pick(rng.next_u64());
            let m = &maps[i];
            for a in 0..d {
                next[a] = m[a * n + d] + (0..d).map(|j| m[a * n + j] * x[j]).sum::<f64>();
            }
            x.copy_from_slice(&next);
            i
        };
        let per = (xs.len() / d).min(CHUNK);
        for _ in 0..self.settings.burn_in {
            c = keep * c + tint[step(&mut x, rng)];
        }
        let mut left = total;
        while left > 0 && !self.cancelled() {
            let here = left.min(per);
            for (p, cp) in xs[..d * here].chunks_exact_mut(d).zip(cs.iter_mut()) {
                let i = step(&mut x, rng);
                p.copy_from_slice(&x);
                if COLOUR {
                    c = keep * c + tint[i];
                    *cp = c as f32;
                }
            }
            emit(&xs[..d * here], if COLOUR { &cs[..here] } else { &[] });
            left -= here;
        }
    }

    /// Any automaton: a walk along the incoming arrows of the states that feed
    /// the roots, restarting in a random state now and then unless the walk is
    /// strongly connected.
    fn general_chain<const COLOUR: bool>(&self, rng: &mut Rng, total: usize, emit: &mut dyn FnMut(&[f64], &[f32])) {
        let (inc, plan, root, pieces) = (&self.inc, &self.plan, self.root, &self.pieces);
        let (d, burn_in, strongly_connected) = (self.pieces.dim, self.settings.burn_in, self.single);
        let keep = 1.0 - self.settings.colour_speed;
        let size = plan.states.len();
        // Last point seen in each state; at first, the centroid of its simplex.
        let mut last: Vec<Vec<f64>> = (0..size)
            .map(|s| plan.states[s].as_ref().map_or_else(Vec::new, |p| vec![1.0 / p.dim as f64; p.dim]))
            .collect();
        let mut state = root;
        let mut lambda = last[root].clone();
        let mut next = Vec::with_capacity(lambda.len());
        let mut c = 0.5;
        let restart = if strongly_connected { 0 } else { u64::MAX / 32 };
        // The pieces drawn from the attractor of each state.
        let mut pieces_of: Vec<Vec<usize>> = vec![Vec::new(); size];
        for (i, p) in pieces.pieces.iter().enumerate() {
            pieces_of[p.state].push(i);
        }
        let live: Vec<usize> = (0..size).filter(|&s| !inc.arrows[s].is_empty()).collect();
        let per = CHUNK;
        let mut xs = vec![0.0; per * d];
        let mut cs = vec![0f32; per];
        let (mut emitted, mut filled) = (0, 0);
        // Steps left before emitting: the burn-in, again after a restart from a
        // state whose last point is not yet on its attractor.
        let mut settle = burn_in;
        let mut converged = vec![false; size];
        while emitted < total {
            if settle == 0 && rng.next_u64() < restart {
                state = live[(rng.next_u64() % live.len() as u64) as usize];
                lambda = last[state].clone();
                if !converged[state] {
                    settle = burn_in;
                }
            }
            let Some(alias) = &inc.alias[state] else {
                state = root;
                lambda = last[root].clone();
                continue;
            };
            let i = alias.pick(rng.next_u64());
            let (src, m) = &inc.arrows[state][i];
            c = keep * c + inc.colour[state][i];
            let (rows, cols) = (plan.state(*src).dim, lambda.len());
            next.clear();
            next.extend(
                m.chunks_exact(cols).take(rows).map(|row| row.iter().zip(&lambda).map(|(a, b)| a * b).sum::<f64>()),
            );
            std::mem::swap(&mut lambda, &mut next);
            state = *src;
            last[state].clone_from(&lambda);
            if settle > 0 {
                settle -= 1;
                continue;
            }
            converged[state] = true;
            let here = &pieces_of[state];
            if !here.is_empty() {
                let piece = &pieces.pieces[here[(rng.next_u64() % here.len() as u64) as usize]];
                let n = lambda.len();
                for a in 0..d {
                    xs[filled * d + a] = (0..n).map(|i| piece.control[a * n + i] * lambda[i]).sum();
                }
                cs[filled] = c as f32;
                filled += 1;
                emitted += 1;
                if filled == per || emitted == total {
                    emit(&xs[..filled * d], if COLOUR { &cs[..filled] } else { &[] });
                    filled = 0;
                    if self.cancelled() {
                        return;
                    }
                }
            }
        }
    }
}

/// Two affine walks in the plane, interleaved, for `xs.len() / 2` points
/// in all (walk 0 gives the even ones) from `at`, into `xs` (and `cs` when
/// `COLOUR`): a function of its own so that the points, the colours and the
/// generator stay in registers. The steps of the two walks are independent,
/// so each one's multiplications overlap the other's.
#[inline(never)]
fn walk_plane<const COLOUR: bool>(
    maps: &[[f64; 7]],
    alias: &Alias,
    rng: &mut Rng,
    keep: f64,
    at: [[f64; 3]; 2],
    xs: &mut [f64],
    cs: &mut [f32],
) -> [[f64; 3]; 2] {
    let mut r = rng.clone();
    let [[mut x0, mut y0, mut c0], [mut x1, mut y1, mut c1]] = at;
    let n = xs.len() / 2;
    let mut pairs = xs.chunks_exact_mut(4);
    let mut colours = cs.chunks_exact_mut(2);
    for (p, cp) in (&mut pairs).zip(&mut colours) {
        let (a, b) = (alias.pick(r.next_u64()), alias.pick(r.next_u64()));
        let (m, k) = (&maps[a], &maps[b]);
        (x0, y0) = (m[0] * x0 + m[1] * y0 + m[2], m[3] * x0 + m[4] * y0 + m[5]);
        (x1, y1) = (k[0] * x1 + k[1] * y1 + k[2], k[3] * x1 + k[4] * y1 + k[5]);
        p.copy_from_slice(&[x0, y0, x1, y1]);
        if COLOUR {
            c0 = keep * c0 + m[6];
            c1 = keep * c1 + k[6];
            cp.copy_from_slice(&[c0 as f32, c1 as f32]);
        }
    }
    if n % 2 == 1 {
        // The odd point out: walk 0's.
        let m = &maps[alias.pick(r.next_u64())];
        (x0, y0) = (m[0] * x0 + m[1] * y0 + m[2], m[3] * x0 + m[4] * y0 + m[5]);
        xs[2 * n - 2..].copy_from_slice(&[x0, y0]);
        if COLOUR {
            c0 = keep * c0 + m[6];
            cs[n - 1] = c0 as f32;
        }
    }
    *rng = r;
    [[x0, y0, c0], [x1, y1, c1]]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn alias_follows_weights() {
        let a = Alias::new(&[1.0, 3.0, 0.0, 4.0]);
        let mut rng = Rng::new(7);
        let mut counts = [0usize; 4];
        let n = 400_000;
        for _ in 0..n {
            counts[a.pick(rng.next_u64())] += 1;
        }
        // Binomial standard deviation is at most sqrt(n)/2 ≈ 316; allow 5σ.
        for (c, w) in counts.iter().zip([1.0, 3.0, 0.0, 4.0]) {
            assert!((*c as f64 - n as f64 * w / 8.0).abs() < 1600.0, "{counts:?}");
        }
        assert_eq!(counts[2], 0);
    }
}
