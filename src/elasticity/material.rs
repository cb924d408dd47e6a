//! Isotropic linear elastic material in plane strain.

use serde::{Deserialize, Serialize};

/// Largest Young's modulus accepted \[Pa\]: 50 times steel's, beyond any dam or rock.
pub const MAX_YOUNG: f64 = 1e13;
/// Largest density accepted [kg/m³]: four times osmium's, the densest element.
pub const MAX_DENSITY: f64 = 1e5;

/// Young's modulus E \[Pa\], Poisson's ratio ν and density ρ [kg/m³].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    #[serde(rename = "E")]
    pub young: f64,
    #[serde(rename = "nu")]
    pub poisson: f64,
    #[serde(rename = "rho")]
    pub density: f64,
}

impl Material {
    /// Lamé coefficients in plane strain: μ = E / (2(1+ν)), λ = Eν / ((1+ν)(1−2ν)).
    pub fn lame(&self) -> (f64, f64) {
        let (e, nu) = (self.young, self.poisson);
        (e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), e / (2.0 * (1.0 + nu)))
    }

    /// Material with given Lamé coefficients: E = μ(3λ+2μ)/(λ+μ), ν = λ/(2(λ+μ)).
    pub fn from_lame(lambda: f64, mu: f64) -> Self {
        Material {
            young: mu * (3.0 * lambda + 2.0 * mu) / (lambda + mu),
            poisson: lambda / (2.0 * (lambda + mu)),
            density: 0.0,
        }
    }

    /// Checks 0 < E ≤ [`MAX_YOUNG`], −1 < ν < 1/2 and 0 ≤ ρ ≤ [`MAX_DENSITY`]; the message
    /// names the offending value.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.young > 0.0 && self.young.is_finite()) {
            return Err(format!("Young's modulus E = {} must be positive", self.young));
        }
        if self.young > MAX_YOUNG {
            return Err(format!(
                "Young's modulus E = {:e} Pa exceeds {MAX_YOUNG:e} Pa, 50 times steel's: no dam or rock is that \
                 stiff (E is in Pa)",
                self.young
            ));
        }
        if self.density > MAX_DENSITY {
            return Err(format!(
                "density rho = {:e} kg/m^3 exceeds {MAX_DENSITY:e} kg/m^3, four times that of osmium, the densest \
                 element",
                self.density
            ));
        }
        if !(self.poisson > -1.0 && self.poisson < 0.5) {
            return Err(format!("Poisson's ratio nu = {} must lie in (-1, 0.5)", self.poisson));
        }
        if !(self.density >= 0.0 && self.density.is_finite()) {
            return Err(format!("density rho = {} must be non-negative", self.density));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lame_round_trip() {
        let m = Material { young: 3e10, poisson: 0.2, density: 0.0 };
        let (l, mu) = m.lame();
        let back = Material::from_lame(l, mu);
        assert!((back.young / m.young - 1.0).abs() < 1e-14);
        assert!((back.poisson - m.poisson).abs() < 1e-14);
        assert!(Material { poisson: 0.5, ..m }.validate().is_err());
        assert!(Material { young: 0.0, ..m }.validate().is_err());
    }
}
