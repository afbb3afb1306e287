//! Convergence checks of the rule weights of polygon-mesh subdivision
//! (Doo-Sabin's quad rule, Loop's), before a mesh is subdivided: the
//! necessary eigenvalue conditions at each stencil, then the joint spectral
//! radius bounds of the regular patch as an IFS.

use std::f64::consts::PI;

use super::jsr::{JsrSettings, Verdict, jsr, jsr_verdict};
use crate::mesh::{LoopWeights, QuadWeights};

/// Rule weights that make the subdivision diverge, or that are not numbers.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum WeightsError {
    /// A weight that is not a finite number.
    #[error("{scheme} weight {name} = {value} is not a finite number")]
    NotFinite {
        /// The scheme (`doo-sabin`, `loop`).
        scheme: &'static str,
        /// The weight's name.
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// Weights for which the subdivision diverges.
    #[error("{weights}: {why}")]
    Diverges {
        /// The weights, named with their values.
        weights: String,
        /// Which condition fails, with the numbers.
        why: String,
    },
}

/// What the convergence check of rule weights found.
#[derive(Clone, Debug, PartialEq)]
pub enum WeightsVerdict {
    /// The joint spectral radius bounds of the regular patch prove convergence.
    Converges,
    /// Not decided; why.
    Undecided(String),
}

/// Checks the weights before subdividing: finite, the face rule's
/// eigenvalues on the differences below 1 in modulus (necessary), and for
/// mirror-symmetric weights (`β = γ`) the joint spectral radius bounds of
/// the shipped regular patch `doo_sabin_quad` (sufficient when they decide).
///
/// # Errors
/// [`WeightsError`] naming the weights and what fails.
pub fn check_quad_weights(weights: &QuadWeights) -> Result<WeightsVerdict, WeightsError> {
    for (name, x) in [("alpha", weights.alpha), ("beta", weights.beta), ("gamma", weights.gamma)] {
        if !x.is_finite() {
            return Err(WeightsError::NotFinite { scheme: "doo-sabin", name, value: x });
        }
    }
    let named = format!(
        "doo-sabin weights alpha = {}, beta = {}, gamma = {} (opposite corner {})",
        weights.alpha,
        weights.beta,
        weights.gamma,
        weights.delta()
    );
    let [l1, l2, _] = weights.face_eigenvalues();
    if l1 >= 1.0 || l2 >= 1.0 {
        return Err(WeightsError::Diverges {
            weights: named.clone(),
            why: format!(
                "the face rule has eigenvalues of modulus {l1:.6} (twice) and {l2:.6} on the differences; \
             one is not below 1, so faces do not shrink to points: the subdivision diverges"
            ),
        });
    }
    if weights.beta != weights.gamma {
        return Ok(WeightsVerdict::Undecided(format!(
            "{named}: beta ≠ gamma makes the quad rule chiral; its convergence is not decided beyond the face rule's eigenvalues"
        )));
    }
    let Some(design) = crate::format::builtin_design("doo_sabin_quad") else {
        return Ok(WeightsVerdict::Undecided("the regular patch is not available".into()));
    };
    let values =
        [("alpha", weights.alpha), ("beta", weights.beta), ("gamma", weights.gamma)].map(|(n, v)| (n.to_string(), v));
    let instance = match crate::family::instantiate(&design, &values) {
        Ok(instance) => instance,
        Err(e) => return Ok(WeightsVerdict::Undecided(format!("{named}: {e}"))),
    };
    match jsr(&instance.automaton, &JsrSettings::quick()) {
        Ok(bounds) => match bounds.verdict() {
            Verdict::Converges => Ok(WeightsVerdict::Converges),
            Verdict::Diverges => Err(WeightsError::Diverges {
                weights: named.clone(),
                why: format!(
                    "the regular patch diverges ({}): choose weights inside the convergence domain",
                    bounds.witness_text()
                ),
            }),
            Verdict::Undecided => {
                Ok(WeightsVerdict::Undecided(format!("{named}: convergence is undecided ({bounds})")))
            }
        },
        Err(e) => Ok(WeightsVerdict::Undecided(format!("{named}: {e}"))),
    }
}

/// Checks the weights before subdividing a mesh whose interior vertices
/// have the valences `valences`: finite; at each valence the 1-ring's
/// eigenvalues on the differences below 1 in modulus (necessary); the
/// joint spectral radius bounds of the regular box-spline hexagon with
/// these weights (Schaefer et al. 2005 §3.2's six-map IFS; sufficient for the
/// regular parts when they decide).
///
/// # Errors
/// [`WeightsError`] naming the weights and what fails.
pub fn check_loop_weights(weights: &LoopWeights, valences: &[usize]) -> Result<WeightsVerdict, WeightsError> {
    for (name, x) in [("w", weights.w), ("sigma", weights.sigma)] {
        if !x.is_finite() {
            return Err(WeightsError::NotFinite { scheme: "loop", name, value: x });
        }
    }
    let named = format!("loop weights w = {}, sigma = {}", weights.w, weights.sigma);
    for &n in valences.iter().filter(|&&n| n >= 3) {
        let average = weights.sigma * weights.lambda1(n).powi(2);
        let worst =
            (1..n).map(|k| (weights.w + (1.0 - 2.0 * weights.w) * (2.0 * PI * k as f64 / n as f64).cos()).abs());
        let worst = worst.fold(average.abs(), f64::max);
        if worst >= 1.0 {
            let culprit = if average.abs() >= 1.0 { "sigma" } else { "w" };
            return Err(WeightsError::Diverges {
                weights: named.clone(),
                why: format!(
                    "at a vertex of valence {n} the 1-ring rule has an eigenvalue of modulus {worst:.6} \
                 on the differences (`{culprit}` puts it there); the subdivision diverges"
                ),
            });
        }
    }
    // The regular hexagon's IFS, exact from the decimals given.
    let exact = |x: f64| crate::algebra::Num::from_f64(x).as_rational();
    let (Some(w), Some(ring6)) = (exact(weights.w), exact(weights.ring(6))) else {
        return Ok(WeightsVerdict::Undecided(format!("{named}: not a decimal")));
    };
    let beta = ring6 / num_rational::BigRational::from_integer(6.into());
    let ifs = crate::schemes::box_spline_hexagon(&w, &beta);
    let mut automaton = crate::automaton::Automaton::new("box_spline");
    let n = ifs.control.len();
    let undecided = |e: crate::automaton::AutomatonError| WeightsVerdict::Undecided(format!("{named}: {e}"));
    let state = match automaton.add_state(crate::space::State::new("hexagon", n, crate::space::CellKind::Free)) {
        Ok(state) => state,
        Err(e) => return Ok(undecided(e)),
    };
    for (k, block) in ifs.blocks.iter().enumerate() {
        let matrix = crate::schemes::to_f64(block).transpose();
        let arrow =
            crate::automaton::Arrow { name: format!("T{k}"), kind: crate::automaton::ArrowKind::Subdivision, matrix };
        if let Err(e) = automaton.add_arrow(state, state, arrow) {
            return Ok(undecided(e));
        }
    }
    match jsr_verdict(&automaton, &JsrSettings::default()) {
        Ok(Verdict::Converges) => Ok(WeightsVerdict::Converges),
        Ok(Verdict::Diverges) => Err(WeightsError::Diverges {
            weights: named.clone(),
            why: "the regular box-spline patch with these weights diverges (a product of its six maps \
                  does not contract): choose `w` and `sigma` inside the convergence domain"
                .into(),
        }),
        Ok(Verdict::Undecided) => Ok(WeightsVerdict::Undecided(format!(
            "{named}: the convergence of the regular patch is undecided within the budget"
        ))),
        Err(e) => Ok(WeightsVerdict::Undecided(format!("{named}: {e}"))),
    }
}
