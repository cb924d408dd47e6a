//! The case's `.geo` and scene files.

use super::*;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

impl DamCase {
    /// "rigid" or "rock".
    pub fn kind(&self) -> &'static str {
        match self.foundation {
            Foundation::Rigid => "rigid",
            Foundation::Rock { .. } => "rock",
        }
    }

    /// E_rock / E_concrete, if there is rock.
    pub fn rock_ratio(&self) -> Option<f64> {
        match self.foundation {
            Foundation::Rigid => None,
            Foundation::Rock { ratio } => Some(ratio),
        }
    }

    /// The `.geo` file.
    pub fn geo(&self) -> String {
        let h = self.height;
        let mut geo = format!(
            "// Battery case of seed {}: a gravity dam, plane strain, SI units.\nh = {};\nhb = {};\nhr = {};\n",
            self.seed,
            h / 12.0,
            h / 48.0,
            h / 4.0
        );
        let outline = self.outline();
        let sizes = ["hb", "hb", "h", "h", "h"];
        for (i, p) in outline.iter().enumerate() {
            writeln!(geo, "Point({}) = {{{}, {}, 0, {}}};", i + 1, p[0], p[1], sizes[i]).unwrap();
        }
        let n = outline.len();
        for i in 0..n {
            writeln!(geo, "Line({}) = {{{}, {}}};", i + 1, i + 1, (i + 1) % n + 1).unwrap();
        }
        let upstream = (4..=n).map(|i| i.to_string()).collect::<Vec<_>>().join(", ");
        let loops = (1..=n).map(|i| i.to_string()).collect::<Vec<_>>().join(", ");
        writeln!(geo, "Curve Loop(1) = {{{loops}}};").unwrap();
        let mut physical = format!(
            "Physical Curve(\"base\") = {{1}};\nPhysical Curve(\"downstream\") = {{2}};\n\
             Physical Curve(\"crest\") = {{3}};\nPhysical Curve(\"upstream\") = {{{upstream}}};\n"
        );
        match self.gallery {
            Some(g) => {
                let size = g.width.min(g.height) / 3.0;
                for (i, p) in DamCase::gallery_outline(&g).iter().enumerate() {
                    writeln!(geo, "Point({}) = {{{}, {}, 0, {size}}};", 11 + i, p[0], p[1]).unwrap();
                }
                for i in 0..4 {
                    writeln!(geo, "Line({}) = {{{}, {}}};", 11 + i, 11 + i, 11 + (i + 1) % 4).unwrap();
                }
                geo.push_str("Curve Loop(2) = {11, 12, 13, 14};\nPlane Surface(1) = {1, 2};\n");
                physical.push_str("Physical Curve(\"gallery\") = {11, 12, 13, 14};\n");
            }
            None => geo.push_str("Plane Surface(1) = {1};\n"),
        }
        physical.push_str("Physical Surface(\"concrete\") = {1};\n");
        if let Foundation::Rock { .. } = self.foundation {
            geo.push_str(&self.rock_geo());
            physical.push_str(
                "Physical Curve(\"reservoir_floor\") = {21};\nPhysical Curve(\"ground\") = {22};\n\
                 Physical Curve(\"rock_sides\") = {23, 25};\nPhysical Curve(\"rock_bottom\") = {24};\n\
                 Physical Surface(\"rock\") = {2};\n",
            );
        }
        geo + &physical
    }

    /// The rock block's points, lines and surface: extent B up- and downstream, depth B below
    /// the lower end of the base.
    fn rock_geo(&self) -> String {
        let toe = self.toe();
        let extent = toe[0];
        let bottom = toe[1].min(0.0) - extent;
        let points = [[-extent, 0.0], [toe[0] + extent, toe[1]], [toe[0] + extent, bottom], [-extent, bottom]];
        let mut geo = String::new();
        for (i, p) in points.iter().enumerate() {
            writeln!(geo, "Point({}) = {{{}, {}, 0, hr}};", 21 + i, p[0], p[1]).unwrap();
        }
        geo.push_str(
            "Line(21) = {21, 1};\nLine(22) = {2, 22};\nLine(23) = {22, 23};\nLine(24) = {23, 24};\n\
             Line(25) = {24, 21};\nCurve Loop(3) = {21, 1, 22, 23, 24, 25};\nPlane Surface(2) = {-3};\n",
        );
        geo
    }

    /// The scene file, its geometry `geometry` beside it.
    pub fn scene(&self, geometry: &str) -> String {
        let mut toml = format!(
            "# Battery case of seed {}.\ngeometry = {geometry:?}\n\n[mesh]\norder = {}\n\n\
             [materials.concrete]\nE = {E_CONCRETE:?}\nnu = {NU_CONCRETE:?}\nrho = {RHO_CONCRETE:?}\n\n",
            self.seed, self.order
        );
        if let Some(ratio) = self.rock_ratio() {
            toml += &format!("[materials.rock]\nE = {:?}\nnu = {NU_ROCK:?}\nrho = 0.0\n\n", ratio * E_CONCRETE);
        }
        // the reference has no hydrodynamic pressure
        toml += &format!(
            "[loads]\ngravity = {GRAVITY:?}\nacceleration = [{:?}, 0.0]\nwestergaard = false\n\n",
            self.acceleration
        );
        let hydrostatic = |curve: &str, level: f64| {
            format!("[boundary.{curve}]\nrole = \"neumann\"\nhydrostatic = {{ level = {level:?}, density = {RHO_WATER:?} }}\n\n")
        };
        let free = |curve: &str| format!("[boundary.{curve}]\nrole = \"free\"\n\n");
        let tailwater = |curve: &str| self.tailwater.map_or_else(|| free(curve), |t| hydrostatic(curve, t));
        toml += &hydrostatic("upstream", self.reservoir);
        toml += &tailwater("downstream");
        toml += &free("crest");
        if self.gallery.is_some() {
            toml += &free("gallery");
        }
        let mut law = format!("friction = {:?}\n", self.friction);
        if self.cohesion > 0.0 {
            law += &format!("cohesion = {:?}\n", self.cohesion);
        }
        if let Some(b) = self.bond {
            law += &format!("tensile_strength = {:?}\nfracture_energy = {:?}\n", b.tensile_strength, b.fracture_energy);
        }
        toml += &match self.foundation {
            Foundation::Rigid => format!("[boundary.base]\nrole = \"contact\"\n\n[contact]\n{law}max_iter = 100\n\n"),
            Foundation::Rock { .. } => {
                hydrostatic("reservoir_floor", self.reservoir)
                    + &tailwater("ground")
                    + "[boundary.rock_bottom]\nrole = \"dirichlet\"\n\n\
                       [boundary.rock_sides]\nrole = \"dirichlet\"\nfix = \"x\"\n\n"
                    + &format!("[joints.base]\n{law}slave = \"concrete\"\n\n[contact]\nmax_iter = 100\n\n")
            }
        };
        toml += &format!("[uplift]\nheadwater = {:?}\n", self.reservoir);
        if let Some(t) = self.tailwater {
            toml += &format!("tailwater = {t:?}\n");
        }
        if let Some(d) = self.drains {
            toml += &format!("drains = {{ x = {:?}, efficiency = {:?} }}\n", d.distance, d.efficiency);
        }
        toml + &format!("crack = \"{}\"\nheel = [0.0, 0.0]\n", self.crack.name())
    }

    /// Writes `case.geo` and `case.toml` into `dir`; the scene's path.
    pub fn write(&self, dir: &Path) -> std::io::Result<PathBuf> {
        std::fs::create_dir_all(dir)?;
        std::fs::write(dir.join("case.geo"), self.geo())?;
        let scene = dir.join("case.toml");
        std::fs::write(&scene, self.scene("case.geo"))?;
        Ok(scene)
    }

    /// gmsh's size factor of this case's run.
    pub fn size_factor(&self) -> f64 {
        SIZE_FACTOR[self.order - 1]
    }
}
