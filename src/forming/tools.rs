//! Rigid axisymmetric tools in the (r, z) meridian plane.
//!
//! The sheet's mid-surface starts at z = 0. The punch sits above it and moves down (−z); the
//! die lies below with its flat face at `z = −t/2`; the blank holder presses the flange down
//! onto the die with a prescribed force (applied as nodal loads, see [`super::solver`]).
//!
//! Every tool gives, for a point p, the distance `d(p)` from its surface (> 0 outside) and the
//! unit outward normal `n(p)` pointing from the tool toward p. The contact gap of a sheet node
//! is `d − t_node/2` (mid-surface offset).
//!
//! * [`Punch`]: flat face of radius `R − ρ_p` at `z_tip`, corner (profile) radius ρ_p, cylinder
//!   of radius R above. Hemispherical: `ρ_p = R`.
//! * [`Die`]: flat face at `z_face` for `r ≥ R_d + ρ_d`, profile arc of radius ρ_d centred at
//!   `(R_d + ρ_d, z_face − ρ_d)`, vertical throat wall at `r = R_d` (opening radius R_d).

/// The punch (moves with velocity `(0, −speed)`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Punch {
    /// Punch radius R (in).
    pub radius: f64,
    /// Profile (corner) radius ρ_p (in); `= radius` for a hemispherical punch.
    pub profile_radius: f64,
    /// Current z of the lowest point of the punch (in).
    pub tip_z: f64,
}

/// The die (stationary).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Die {
    /// Opening (throat) radius R_d (in).
    pub opening_radius: f64,
    /// Profile radius ρ_d (in).
    pub profile_radius: f64,
    /// z of the flat face (in).
    pub face_z: f64,
}

fn unit(v: [f64; 2]) -> ([f64; 2], f64) {
    let n = (v[0] * v[0] + v[1] * v[1]).sqrt();
    if n > 0.0 {
        ([v[0] / n, v[1] / n], n)
    } else {
        ([0.0, 0.0], 0.0)
    }
}

impl Punch {
    /// Centre of the profile arc `(R − ρ_p, z_tip + ρ_p)`.
    pub fn corner_center(&self) -> [f64; 2] {
        [
            self.radius - self.profile_radius,
            self.tip_z + self.profile_radius,
        ]
    }

    /// `(d, n)`: signed distance of p from the punch surface and the outward normal.
    pub fn distance(&self, p: [f64; 2]) -> (f64, [f64; 2]) {
        let c = self.corner_center();
        if p[1] <= c[1] {
            if p[0] <= c[0] {
                (self.tip_z - p[1], [0.0, -1.0])
            } else {
                let (n, len) = unit([p[0] - c[0], p[1] - c[1]]);
                (len - self.profile_radius, n)
            }
        } else {
            (p[0] - self.radius, [1.0, 0.0])
        }
    }

    /// The punch outline from the axis up to height `height` above the tip.
    pub fn outline(&self, height: f64) -> Vec<[f64; 2]> {
        let c = self.corner_center();
        let mut pts = vec![[0.0, self.tip_z]];
        let k = 24;
        for i in 0..=k {
            let a = -std::f64::consts::FRAC_PI_2 * (1.0 - i as f64 / k as f64);
            pts.push([
                c[0] + self.profile_radius * a.cos(),
                c[1] + self.profile_radius * a.sin(),
            ]);
        }
        pts.push([self.radius, self.tip_z + height.max(self.profile_radius)]);
        pts
    }
}

impl Die {
    /// Centre of the profile arc `(R_d + ρ_d, z_face − ρ_d)`.
    pub fn corner_center(&self) -> [f64; 2] {
        [
            self.opening_radius + self.profile_radius,
            self.face_z - self.profile_radius,
        ]
    }

    /// `(d, n)`: signed distance of p from the die surface and the outward normal.
    pub fn distance(&self, p: [f64; 2]) -> (f64, [f64; 2]) {
        let c = self.corner_center();
        if p[0] >= c[0] {
            (p[1] - self.face_z, [0.0, 1.0])
        } else if p[1] >= c[1] {
            let (n, len) = unit([p[0] - c[0], p[1] - c[1]]);
            (len - self.profile_radius, n)
        } else {
            (self.opening_radius - p[0], [-1.0, 0.0])
        }
    }

    /// The die outline from depth `depth` below the face up the throat, over the profile and
    /// out to radius `r_max`.
    pub fn outline(&self, depth: f64, r_max: f64) -> Vec<[f64; 2]> {
        let c = self.corner_center();
        let mut pts = vec![[
            self.opening_radius,
            self.face_z - depth.max(self.profile_radius),
        ]];
        let k = 16;
        for i in 0..=k {
            let a = std::f64::consts::PI - std::f64::consts::FRAC_PI_2 * i as f64 / k as f64;
            pts.push([
                c[0] + self.profile_radius * a.cos(),
                c[1] + self.profile_radius * a.sin(),
            ]);
        }
        pts.push([r_max.max(c[0]), self.face_z]);
        pts
    }
}

/// Which tool a contact constraint belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ToolId {
    /// The punch.
    Punch,
    /// The die.
    Die,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hemispherical_punch_distance_is_radial() {
        let p = Punch {
            radius: 1.0,
            profile_radius: 1.0,
            tip_z: 0.0,
        };
        let (d, n) = p.distance([0.6, 0.2]);
        let c = [0.0, 1.0];
        let len = ((0.6f64 - c[0]).powi(2) + (0.2f64 - c[1]).powi(2)).sqrt();
        assert!((d - (len - 1.0)).abs() < 1e-14);
        assert!((n[0] * n[0] + n[1] * n[1] - 1.0).abs() < 1e-14 && n[1] < 0.0);
    }

    #[test]
    fn die_regions() {
        let d = Die {
            opening_radius: 1.0,
            profile_radius: 0.25,
            face_z: 0.0,
        };
        assert_eq!(d.distance([2.0, 0.1]), (0.1, [0.0, 1.0]));
        assert_eq!(d.distance([0.5, -1.0]), (0.5, [-1.0, 0.0]));
        let (g, n) = d.distance([1.0, -0.25]);
        assert!(g.abs() < 1e-14 && (n[0] + 1.0).abs() < 1e-14);
    }
}
