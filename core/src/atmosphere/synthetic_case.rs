//! [`SyntheticCase`]: one atmosphere of the synthetic set (see [`super::synthetic_set`]), the
//! deterministic factor f(h)·k(h) it scales the mean by, and the altitudes of its blend.

use super::density_model::Atmosphere;

/// Altitude (m) below which a case's `f_below` applies.
pub const SYNTHETIC_BLEND_BOTTOM_M: f64 = 60_000.0;
/// Altitude (m) above which a case's `f_above` applies.
pub const SYNTHETIC_BLEND_TOP_M: f64 = 80_000.0;
/// Anchor altitude (m) about which a high-latitude case steepens the lower atmosphere.
pub const SYNTHETIC_STEEPEN_ANCHOR_M: f64 = 40_000.0;

/// One atmosphere of the set: density factors relative to the mean.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SyntheticCase {
    /// ρ/ρ̄ above 80 km (before the perturbation).
    pub factor_above: f64,
    /// ρ/ρ̄ below 60 km (before the perturbation), times the steepening k(h) when
    /// `scale_height_factor` ≠ 1.
    pub factor_below: f64,
    /// s: the lower atmosphere's scale heights are s times the mean's (1 = the mean's shape).
    pub scale_height_factor: f64,
    /// Multiplier of the set's perturbation scale for this case (1 = the set's).
    pub perturbation_factor: f64,
}

impl SyntheticCase {
    /// A case with the mean's shape (s = 1) and the set's perturbation.
    pub fn scaled(factor_above: f64, factor_below: f64) -> Self {
        SyntheticCase {
            factor_above,
            factor_below,
            scale_height_factor: 1.0,
            perturbation_factor: 1.0,
        }
    }

    /// The deterministic factor ρ/ρ̄ at `altitude_m` over the mean `mean`: f(h) of the module
    /// documentation times the steepening k(h) below 60 km, blended out over 60–80 km (k = 1
    /// exactly when s = 1).
    pub fn factor(&self, mean: &impl Atmosphere, altitude_m: f64) -> f64 {
        let h = altitude_m.min(SYNTHETIC_BLEND_BOTTOM_M);
        let ln_k = (1.0 / self.scale_height_factor - 1.0)
            * (mean.density(h) / mean.density(SYNTHETIC_STEEPEN_ANCHOR_M)).ln();
        self.blend(altitude_m, ln_k)
    }

    /// exp of ln f_below + ln k blended into ln f_above over 60–80 km (smoothstep).
    fn blend(&self, altitude_m: f64, ln_k: f64) -> f64 {
        let u = ((altitude_m - SYNTHETIC_BLEND_BOTTOM_M)
            / (SYNTHETIC_BLEND_TOP_M - SYNTHETIC_BLEND_BOTTOM_M))
            .clamp(0.0, 1.0);
        let s = u * u * (3.0 - 2.0 * u);
        let (lb, la) = (self.factor_below.ln() + ln_k, self.factor_above.ln());
        (lb + (la - lb) * s).exp()
    }

    /// One line: the factors, and s and the perturbation factor where they are not 1.
    pub fn describe(&self) -> String {
        let mut d = format!(
            "f_above {:>4} f_below {:>4}",
            self.factor_above, self.factor_below
        );
        if self.scale_height_factor != 1.0 || self.perturbation_factor != 1.0 {
            d.push_str(&format!(
                " scale height x {} perturbation x {}",
                self.scale_height_factor, self.perturbation_factor
            ));
        }
        d.push_str(&format!(" ({})", self.season()));
        d
    }

    /// A short description: "high latitude", "cold / polar", "dusty season", "mean" or "mixed".
    pub fn season(&self) -> &'static str {
        if self.scale_height_factor < 1.0 {
            return "high latitude";
        }
        match (self.factor_above, self.factor_below) {
            (a, b) if a < 1.0 && b > 1.0 => "cold / polar",
            (a, b) if a > 1.0 && b < 1.0 => "dusty season",
            (a, b) if a == 1.0 && b == 1.0 => "mean",
            _ => "mixed",
        }
    }
}
