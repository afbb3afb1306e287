//! The random sources of the chaos game: its settings, the generator, the
//! alias tables that pick an arrow, and the default probabilities.

use super::settings::EvalError;

/// Default number of discarded first iterations of each chain.
pub const DEFAULT_BURN_IN: usize = 64;
/// Floor of the default probabilities, relative to the mean `|det|`.
pub const SINGULAR_FLOOR: f64 = 0.01;

/// Settings of a chaos game.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct RandomSettings {
    /// Points to emit.
    pub points: usize,
    /// Seed: the same seed gives the same points, whatever the thread count.
    pub seed: u64,
    /// Iterations discarded at the start of each chain.
    pub burn_in: usize,
    /// Explicit probabilities by arrow name (normalised per target state); others by `|det|`.
    pub probabilities: Vec<(String, f64)>,
    /// Worker threads (`None`: all cores).
    pub threads: Option<usize>,
    /// Independent chains (fixed, so output does not depend on threads).
    pub chains: usize,
    /// Run even a system whose joint spectral radius bounds prove it diverges.
    pub force: bool,
    /// The points are held in memory: more than this many bytes is refused.
    pub memory_limit: usize,
    /// Explicit colour coordinates in `[0, 1]` by arrow name; the others are
    /// spread evenly over `[0, 1]` in arrow order (as flame editors do).
    pub colours: Vec<(String, f64)>,
    /// How far each step moves the colour coordinate towards the colour of
    /// the arrow it applies: `c ← (1 − s) c + s c_arrow` (flam3's colour speed, default 1/2).
    pub colour_speed: f64,
    /// Told the chains done of all, as [`crate::geometry::PointBatches::fold`] and
    /// [`super::ChaosGame::stream`] go.
    pub progress: Option<crate::progress::Progress>,
    /// Once set, [`crate::geometry::PointBatches::fold`] stops taking batches (its result is
    /// then partial: the caller that set it discards it).
    pub cancel: Option<crate::progress::Cancel>,
    /// Subdivision arrows left out of the walk (a subset of the attractor,
    /// as [`super::EvalSettings::dropped`] does for the deterministic evaluation).
    pub dropped: Vec<String>,
}

impl Default for RandomSettings {
    fn default() -> RandomSettings {
        RandomSettings {
            points: 1_000_000,
            seed: 1,
            burn_in: DEFAULT_BURN_IN,
            probabilities: Vec::new(),
            threads: None,
            chains: 8,
            force: false,
            memory_limit: super::settings::DEFAULT_MEMORY_LIMIT,
            colours: Vec::new(),
            colour_speed: 0.5,
            progress: None,
            cancel: None,
            dropped: Vec::new(),
        }
    }
}

impl RandomSettings {
    /// With a number of points.
    pub fn with_points(mut self, n: usize) -> Self {
        self.points = n;
        self
    }
    /// With a seed.
    pub fn with_seed(mut self, seed: u64) -> Self {
        self.seed = seed;
        self
    }
    /// With a number of chains.
    pub fn with_chains(mut self, chains: usize) -> Self {
        self.chains = chains.max(1);
        self
    }
    /// With threads.
    pub fn with_threads(mut self, threads: usize) -> Self {
        self.threads = Some(threads);
        self
    }
    /// Without the subdivision arrows named `names`.
    pub fn with_dropped(mut self, names: Vec<String>) -> Self {
        self.dropped = names;
        self
    }
}

/// The colour coordinate of subdivision arrow `k` (of `count`, in order)
/// named `name`: as `settings` gives it, else spread evenly over `[0, 1]`
/// in arrow order (as flame editors do).
pub fn arrow_colour(settings: &RandomSettings, k: usize, count: usize, name: &str) -> f64 {
    let even = if count > 1 { k as f64 / (count - 1) as f64 } else { 0.5 };
    settings.colours.iter().find(|(n, _)| n == name).map_or(even, |(_, c)| *c)
}

/// A small, fast generator (wyrand): good statistical quality for sampling.
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// Seeded generator.
    pub fn new(seed: u64) -> Rng {
        Rng(seed ^ 0x9E37_79B9_7F4A_7C15)
    }
    /// Next 64 random bits.
    #[inline(always)]
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0xa076_1d64_78bd_642f);
        let t = u128::from(self.0) * u128::from(self.0 ^ 0xe703_7ed1_a0b4_28db);
        ((t >> 64) ^ t) as u64
    }
}

/// The most samples a chaos game may draw: 2^40, about three hours on one
/// core at 100 million samples a second. A count that cannot finish is
/// refused at once, with the time it would take.
pub const MAX_SAMPLES: usize = 1 << 40;

/// Refuses a sample count over [`MAX_SAMPLES`].
///
/// # Errors
/// [`EvalError::TooManySamples`], with the estimate.
pub fn check_samples(samples: usize) -> Result<(), EvalError> {
    if samples > MAX_SAMPLES {
        return Err(EvalError::TooManySamples { samples: samples as u128, max: MAX_SAMPLES as u128 });
    }
    Ok(())
}

/// Vose's alias table: one random word picks an index with given weights.
#[derive(Clone, Debug)]
pub struct Alias {
    /// `(threshold in 2^32 units, alias)` per slot.
    slots: Vec<(u32, u32)>,
}

impl Alias {
    /// The table of (non-negative, not all zero) weights.
    pub fn new(weights: &[f64]) -> Alias {
        let n = weights.len();
        let total: f64 = weights.iter().sum();
        let mut scaled: Vec<f64> = weights.iter().map(|w| w * n as f64 / total).collect();
        let mut slots = vec![(u32::MAX, 0u32); n];
        let (mut small, mut large): (Vec<usize>, Vec<usize>) = (0..n).partition(|&i| scaled[i] < 1.0);
        while let (Some(s), Some(&l)) = (small.pop(), large.last()) {
            slots[s] = ((scaled[s] * 4_294_967_296.0).min(4_294_967_295.0) as u32, l as u32);
            scaled[l] -= 1.0 - scaled[s];
            if scaled[l] < 1.0 {
                large.pop();
                small.push(l);
            }
        }
        for (i, slot) in slots.iter_mut().enumerate() {
            if slot.0 == u32::MAX {
                *slot = (u32::MAX, i as u32);
            }
        }
        Alias { slots }
    }

    /// An index drawn from one random word.
    #[inline(always)]
    pub fn pick(&self, r: u64) -> usize {
        let i = (((r >> 32) * self.slots.len() as u64) >> 32) as usize;
        let (threshold, alias) = self.slots[i];
        // Branch-free select: the comparison is a coin flip the predictor cannot learn.
        let keep = usize::from((r as u32) < threshold);
        alias as usize ^ ((alias as usize ^ i) & keep.wrapping_neg())
    }
}

/// Default probability weights of arrows: `|det M|` with a floor, for maps
/// of modelling dimension `d`. A square `M` on more than `d + 1` control
/// points is not an affine map of R^d: its area (volume) ratio is that of
/// its dominant invariant subspace, the product of its `d + 1` largest
/// eigenvalue moduli (which is `|det M|` on `d + 1` points; for the
/// sub-patches of a subdivision surface, the same for every map).
pub fn det_weights(matrices: &[&nalgebra::DMatrix<f64>], d: usize) -> Vec<f64> {
    let ratio = |m: &nalgebra::DMatrix<f64>| {
        if !m.is_square() {
            return 0.0;
        }
        if m.nrows() <= d + 1 {
            return m.determinant().abs();
        }
        let Some(eig) = crate::algebra::eigenvalues(m) else { return 0.0 };
        let mut moduli: Vec<f64> = eig.iter().map(|l| l.norm()).collect();
        moduli.sort_by(|a, b| b.total_cmp(a));
        moduli.iter().take(d + 1).product()
    };
    let dets: Vec<f64> = matrices.iter().map(|m| ratio(m)).collect();
    let mean = dets.iter().sum::<f64>() / dets.len().max(1) as f64;
    if mean <= 0.0 {
        return vec![1.0; dets.len()];
    }
    dets.iter().map(|d| d.max(SINGULAR_FLOOR * mean)).collect()
}
