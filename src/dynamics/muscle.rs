//! MuJoCo's muscle model (`mju_muscleGain`, `mju_muscleBias`, `mju_muscleDynamics`; MuJoCo's
//! documentation, "Muscles"): the actuator's length mapped onto the muscle's normalised length L
//! (the `range` it spans over `lengthrange`) and velocity V (in units of L₀ vmax), the active force
//! −F₀ FL(L) FV(V) per unit activation and the passive force −F₀ FP(L); the activation follows
//! ctrl with the time constants of Millard et al. 2013.

use crate::model::Muscle;

/// Smallest denominator (MuJoCo's `mjMINVAL`).
const TINY: f64 = 1e-15;

/// The muscle's peak force F₀ (`force`, or `scale / acc0` when that is negative), its optimal
/// length L₀ and the normalised length of actuator length `len`.
fn normalised(mu: &Muscle, len: f64) -> (f64, f64, f64) {
    let [r0, r1, force, scale, ..] = mu.prm;
    let f0 = if force < 0.0 { scale / mu.acc0.max(TINY) } else { force };
    let [l0, l1] = mu.lengthrange;
    let optimal = (l1 - l0) / (r1 - r0).max(TINY);
    (f0, optimal, r0 + (len - l0) / optimal.max(TINY))
}

/// Active force per unit activation at actuator length `len` and velocity `vel`.
pub fn gain(mu: &Muscle, len: f64, vel: f64) -> f64 {
    let [.., lmin, lmax, vmax, _, fvmax] = mu.prm;
    let (f0, optimal, l) = normalised(mu, len);
    let v = vel / (optimal * vmax).max(TINY);
    // force–length: quadratic rises and falls meeting at 1 (peak), zero outside [lmin, lmax]
    let (a, b) = (0.5 * (lmin + 1.0), 0.5 * (1.0 + lmax));
    let fl = if !(lmin..=lmax).contains(&l) {
        0.0
    } else if l <= a {
        0.5 * ((l - lmin) / (a - lmin).max(TINY)).powi(2)
    } else if l <= 1.0 {
        1.0 - 0.5 * ((1.0 - l) / (1.0 - a).max(TINY)).powi(2)
    } else if l <= b {
        1.0 - 0.5 * ((l - 1.0) / (b - 1.0).max(TINY)).powi(2)
    } else {
        0.5 * ((lmax - l) / (lmax - b).max(TINY)).powi(2)
    };
    // force–velocity: none at −vmax, one at rest, fvmax when lengthening fast
    let y = fvmax - 1.0;
    let fv = if v <= -1.0 {
        0.0
    } else if v <= 0.0 {
        (v + 1.0) * (v + 1.0)
    } else if v <= y {
        fvmax - (y - v) * (y - v) / y.max(TINY)
    } else {
        fvmax
    };
    -f0 * fl * fv
}

/// Passive force at actuator length `len`: half-quadratic beyond the optimal length up to
/// (1 + lmax)/2, linear after it.
pub fn bias(mu: &Muscle, len: f64) -> f64 {
    let [.., lmax, _, fpmax, _] = mu.prm;
    let (f0, _, l) = normalised(mu, len);
    let b = 0.5 * (1.0 + lmax);
    if l <= 1.0 {
        0.0
    } else if l <= b {
        let x = (l - 1.0) / (b - 1.0).max(TINY);
        -f0 * fpmax * 0.5 * x * x
    } else {
        -f0 * fpmax * (0.5 + (l - b) / (b - 1.0).max(TINY))
    }
}

/// act˙ of a muscle at control `ctrl` and activation `act`, with `tau` = [τ_act, τ_deact,
/// smoothing width].
pub fn activation_rate(ctrl: f64, act: f64, [tau_act, tau_deact, width]: [f64; 3]) -> f64 {
    let a = act.clamp(0.0, 1.0);
    let (t_act, t_deact) = (tau_act * (0.5 + 1.5 * a), tau_deact / (0.5 + 1.5 * a));
    let excess = ctrl.clamp(0.0, 1.0) - act;
    let tau = if width < TINY {
        if excess > 0.0 { t_act } else { t_deact }
    } else {
        // a sigmoid over the width, centred on zero excess (MuJoCo's `mju_sigmoid`: a quintic)
        t_deact + (t_act - t_deact) * sigmoid(excess / width + 0.5)
    };
    excess / tau.max(TINY)
}

/// MuJoCo's `mju_sigmoid`: 0 below 0, 1 above 1, and 6x⁵ − 15x⁴ + 10x³ between.
fn sigmoid(x: f64) -> f64 {
    if x <= 0.0 {
        0.0
    } else if x >= 1.0 {
        1.0
    } else {
        x * x * x * (3.0 * x * (2.0 * x - 5.0) + 10.0)
    }
}
