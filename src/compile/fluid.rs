//! The ellipsoid fluid model's constants per geom (MuJoCo's `geom_fluid`): the geom's equivalent
//! ellipsoid and the virtual mass and moment of inertia of the fluid it carries along, from
//! potential flow (Lamb 1932, §§114–115: the κ integrals of an ellipsoid, here by the 15-point
//! Gauss–Kronrod rule MuJoCo's compiler uses, on l = x³/(1 − x)², so that the values match).

use glam::DVec3;

use crate::model::{GeomFluid, GeomType};

/// The semi-axes of the ellipsoid standing in for a geom of `kind` and `size` (a capsule's reach
/// its caps' tips, a cylinder's its faces; other shapes their sizes).
fn semiaxes(kind: GeomType, size: [f64; 3]) -> DVec3 {
    match kind {
        GeomType::Sphere => DVec3::splat(size[0]),
        GeomType::Capsule => DVec3::new(size[0], size[0], size[1] + size[0]),
        GeomType::Cylinder => DVec3::new(size[0], size[0], size[1]),
        _ => DVec3::from_array(size),
    }
}

/// A geom's constants for the ellipsoid model with `coef` (blunt, slender and angular drag,
/// Kutta and Magnus lift).
pub(super) fn geom_fluid(kind: GeomType, size: [f64; 3], coef: [f64; 5]) -> GeomFluid {
    let d = semiaxes(kind, size);
    let volume = 4.0 / 3.0 * std::f64::consts::PI * d.x * d.y * d.z;
    let k = DVec3::new(kappa(d.x, d.y, d.z), kappa(d.y, d.z, d.x), kappa(d.z, d.x, d.y));
    // the moments' factors: (d_j² − d_k²)² |κ_k − κ_j| / |2(d_j² − d_k²) + (d_j² + d_k²)(κ_j − κ_k)|
    let factor = |dj: f64, dk: f64, kj: f64, kk: f64| {
        let diff = dj * dj - dk * dk;
        diff * diff * (kk - kj).abs() / (2.0 * diff + (dj * dj + dk * dk) * (kj - kk)).abs().max(TINY)
    };
    let moment = DVec3::new(factor(d.y, d.z, k.y, k.z), factor(d.z, d.x, k.z, k.x), factor(d.x, d.y, k.x, k.y));
    GeomFluid {
        coef,
        semiaxes: d,
        virtual_mass: DVec3::new(k.x / (2.0 - k.x).max(TINY), k.y / (2.0 - k.y).max(TINY), k.z / (2.0 - k.z).max(TINY)) * volume,
        virtual_inertia: moment * (volume / 5.0),
    }
}

/// Smallest denominator (MuJoCo's `mjMINVAL`).
const TINY: f64 = 1e-15;

/// κ_x = d_x d_y d_z ∫₀^∞ dl / ((d_x² + l) √((d_x² + l)(d_y² + l)(d_z² + l))), symmetric in its
/// last two semi-axes, by 15-point Gauss–Kronrod quadrature on x ∈ [0, 1] with l = s x³/(1 − x)²
/// (s = (d_x³ d_y d_z)^⅖ makes l dimensionless).
fn kappa(dx: f64, dy: f64, dz: f64) -> f64 {
    // the nodes' l = x³/(1 − x)², their dl/dx, and the rule's weights
    const L: [f64; 15] = [
        7.865151709349917e-08, 1.7347976913907274e-05, 0.0003548008144506193, 0.002846636252924549, 0.014094260903596077,
        0.053063261727396636, 0.17041978741317773, 0.5, 1.4036301548686991, 3.9353484827022642, 11.644841677041734,
        39.53187807410903, 177.5711362220801, 1429.4772912937397, 54087.416549217705,
    ];
    const DL: [f64; 15] = [
        5.538677720489877e-05, 0.002080868285293228, 0.016514126520723166, 0.07261900344370877, 0.23985243401862602,
        0.6868318249020725, 1.8551129519182894, 5.0, 14.060031152313941, 43.28941239611009, 156.58546376397112,
        747.9826085305024, 5827.4042950027115, 116754.0197944512, 25482945.327264845,
    ];
    const W: [f64; 15] = [
        0.01146766, 0.03154605, 0.05239501, 0.07032663, 0.08450236, 0.09517529, 0.10221647, 0.10474107, 0.10221647,
        0.09517529, 0.08450236, 0.07032663, 0.05239501, 0.03154605, 0.01146766,
    ];
    let (ix, iy, iz) = (1.0 / (dx * dx), 1.0 / (dy * dy), 1.0 / (dz * dz));
    let scale = (dx * dx * dx * dy * dz).powf(0.4);
    let mut sum = 0.0;
    for i in 0..15 {
        let l = scale * L[i];
        let denom = (1.0 + l * ix) * ((1.0 + l * ix) * (1.0 + l * iy) * (1.0 + l * iz)).sqrt();
        sum += scale * DL[i] / denom * W[i];
    }
    sum * ix
}
