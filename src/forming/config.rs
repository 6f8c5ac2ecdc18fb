//! Configuration of a forming simulation (TOML-readable), with the two documented presets.
//!
//! Units: inch, ton-force, second (stress ton-force/in², velocity in/s, penalty ε in
//! ton-force·s/in — the units of the velocity-form K).

use super::material::Material;
use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};

/// How the shell thickness is updated after a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ThicknessUpdate {
    /// `t ← t·exp(ε̇₃₃ Δt)`, `ε̇₃₃ = −(ε̇_s + ε̇_θ)` from the converged velocities at the start
    /// of the step (explicit; the volume error is first order in Δt).
    Rate,
    /// `t ← t·A_old/A_new` with `A = 2π r_m L`: volume conserved exactly per element.
    Volume,
}

/// How μ* (Eq. 4) is evaluated through the thickness of an element.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MuThroughThickness {
    /// One μ* per Gauss layer from the layer's own rate `ε̄̇(ζ)`. A rigid-plastic section
    /// then behaves like a plastic hinge whose rotation rate is indeterminate, and the Picard
    /// iteration drifts in that mode (measured on the default draw: ~50 iterations per step,
    /// 30 % of the steps converged).
    Layered,
    /// One μ* per element from the mid-surface (membrane) rate. Converges well, but a flat
    /// sheet in pure bending has zero membrane rate, so μ* sits at the cut-off and bending is
    /// over-stiff (punch-force spike in the first steps).
    Midsurface,
    /// One μ* per element from the thickness-RMS rate `sqrt(⟨ε̄̇(ζ)²⟩)` (membrane + bending).
    Rms,
}

/// Picard (direct) iteration on μ* within a step.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Picard {
    /// Converged when `max|v_new − v_old| ≤ tol · max(max|v_new|, v_punch)`.
    pub tol: f64,
    /// Iteration cap per step (the step is then flagged `converged = false`).
    pub max_iterations: usize,
    /// Relaxation ω: `v ← v_old + ω (v_new − v_old)` between iterations (1 = none); with
    /// `aitken` this is the first ω of the step.
    pub relaxation: f64,
    /// Aitken's dynamic relaxation (Irons–Tuck): ω updated from the last two residuals
    /// `r = v_new − v_old`, clamped to [0.05, 2]. Used only when `anderson = 0`.
    pub aitken: bool,
    /// Anderson acceleration depth m (`super::acceleration`); 0 = relaxed (Aitken) Picard.
    /// The history restarts whenever the contact set changes.
    pub anderson: usize,
}

impl Default for Picard {
    fn default() -> Self {
        Picard {
            tol: 1e-3,
            max_iterations: 40,
            relaxation: 0.7,
            aitken: true,
            anderson: 3,
        }
    }
}

/// Punch geometry.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PunchConfig {
    /// Radius R (in).
    pub radius: f64,
    /// Profile radius ρ_p (in); `None` = hemispherical (ρ_p = R).
    pub profile_radius: Option<f64>,
}

/// Die geometry.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DieConfig {
    /// Opening radius R_d (in).
    pub opening_radius: f64,
    /// Profile radius ρ_d (in).
    pub profile_radius: f64,
}

/// Everything that defines a forming run except the contact rule.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct FormingConfig {
    /// Name used in outputs.
    pub name: String,
    /// Initial blank radius (in).
    pub blank_radius: f64,
    /// Initial thickness t₀ (in).
    pub thickness: f64,
    /// Number of elements along the meridian.
    pub elements: usize,
    /// Number of time steps.
    pub steps: usize,
    /// Total punch travel (in).
    pub travel: f64,
    /// Punch speed (in/s); Δt = travel / steps / speed.
    pub punch_speed: f64,
    /// Punch.
    pub punch: PunchConfig,
    /// Die.
    pub die: DieConfig,
    /// Blank-holder force (ton-force), spread over the flange nodes on the flat of the die by
    /// tributary area; 0 = no holder.
    pub holder_force: f64,
    /// Clamp the rim node (v_r = v_z = β = 0).
    pub clamped_rim: bool,
    /// Coulomb friction coefficient μ.
    pub friction: f64,
    /// Friction regularization velocity v₀ (in/s): traction `μ p v_t / sqrt(v_t² + v₀²)`.
    pub friction_v0: f64,
    /// Material (Eq. 4, 38).
    pub material: Material,
    /// Gauss layers through the thickness (1–5).
    pub layers: usize,
    /// How μ* varies through the thickness (see [`MuThroughThickness`]).
    pub mu_through_thickness: MuThroughThickness,
    /// Picard iteration.
    pub picard: Picard,
    /// Rigid-mode drag ζ: `ζ · max K_zz` is added to every v_z diagonal so that K (not only
    /// K + penalty) is invertible — the sheet alone has a free rigid translation in z, and the
    /// `condensed` rule needs K⁻¹. Its force is recorded per step (`drag_force`).
    pub drag: f64,
    /// Thickness update.
    pub thickness_update: ThicknessUpdate,
    /// Compute cond₂ of the system matrix at every Picard iteration (slow; off by default).
    pub cond_per_iteration: bool,
    /// Punch travels (in) at which the sheet state is saved for the profile/thickness figures.
    pub snapshots: Vec<f64>,
}

impl Default for FormingConfig {
    fn default() -> Self {
        FormingConfig::woo_deep_drawing()
    }
}

impl FormingConfig {
    /// The Woo-like deep draw (forming.md): blank radius 2.22 in, t = 0.035 in, hemispherical
    /// punch R = 1.0 in, die opening 1.063 in with profile radius 0.25 in, holder force
    /// 1.0 ton-force, μ = 0.2, 50 elements, 100 steps to 1.0 in travel at 1 in/s, Eq. 38 as
    /// printed.
    pub fn woo_deep_drawing() -> Self {
        FormingConfig {
            name: "woo_deep_drawing".into(),
            blank_radius: 2.22,
            thickness: 0.035,
            elements: 50,
            steps: 100,
            travel: 1.0,
            punch_speed: 1.0,
            punch: PunchConfig {
                radius: 1.0,
                profile_radius: None,
            },
            die: DieConfig {
                opening_radius: 1.063,
                profile_radius: 0.25,
            },
            holder_force: 1.0,
            clamped_rim: false,
            friction: 0.2,
            friction_v0: 1e-2,
            material: Material::default(),
            layers: 5,
            mu_through_thickness: MuThroughThickness::Rms,
            picard: Picard::default(),
            drag: 1e-10,
            thickness_update: ThicknessUpdate::Rate,
            cond_per_iteration: false,
            snapshots: vec![0.25, 0.5, 0.75, 1.0],
        }
    }

    /// The clamped hemispherical-punch stretching test (Ghosh–Hecker geometry, forming.md),
    /// converted to inches: clamp radius 59.18 mm = 2.330 in, punch radius 50.8 mm = 2.0 in,
    /// die profile radius 6.35 mm = 0.25 in; the die flat starts at the clamp, so the opening
    /// radius is 2.330 − 0.25 = 2.080 in (our choice). Sheet of the paper's first example:
    /// t = 0.035 in, μ = 0.2; 50 elements, 100 steps to 0.8 in travel, no holder.
    pub fn ghosh_hecker_stretching() -> Self {
        let mm = 1.0 / 25.4;
        FormingConfig {
            name: "ghosh_hecker_stretching".into(),
            blank_radius: 59.18 * mm,
            punch: PunchConfig {
                radius: 50.8 * mm,
                profile_radius: None,
            },
            die: DieConfig {
                opening_radius: 59.18 * mm - 6.35 * mm,
                profile_radius: 6.35 * mm,
            },
            holder_force: 0.0,
            clamped_rim: true,
            travel: 0.8,
            snapshots: vec![0.2, 0.4, 0.6, 0.8],
            ..FormingConfig::woo_deep_drawing()
        }
    }

    /// Reads a TOML file; missing fields take the Woo-like defaults.
    pub fn from_toml_file(path: &std::path::Path) -> Result<Self> {
        let c: FormingConfig = crate::provenance::read_toml(path)?;
        c.validate()?;
        Ok(c)
    }

    /// Δt = travel / steps / punch speed (s).
    pub fn dt(&self) -> f64 {
        self.travel / self.steps as f64 / self.punch_speed
    }

    /// Checks every field; the message names the field and the valid range.
    pub fn validate(&self) -> Result<()> {
        let pos = |name: &str, v: f64| Error::positive(name, v).map(|_| ());
        let nonneg = |name: &str, v: f64| -> Result<()> {
            if v.is_finite() && v >= 0.0 {
                Ok(())
            } else {
                Err(Error::out_of_range(name, v, "a finite number ≥ 0"))
            }
        };
        pos("blank_radius", self.blank_radius)?;
        pos("thickness", self.thickness)?;
        pos("travel", self.travel)?;
        pos("punch_speed", self.punch_speed)?;
        pos("punch.radius", self.punch.radius)?;
        if let Some(rp) = self.punch.profile_radius {
            pos("punch.profile_radius", rp)?;
            if rp > self.punch.radius {
                return Err(Error::out_of_range(
                    "punch.profile_radius",
                    rp,
                    format!("≤ punch.radius = {}", self.punch.radius),
                ));
            }
        }
        pos("die.opening_radius", self.die.opening_radius)?;
        pos("die.profile_radius", self.die.profile_radius)?;
        nonneg("holder_force", self.holder_force)?;
        nonneg("friction", self.friction)?;
        pos("friction_v0", self.friction_v0)?;
        nonneg("drag", self.drag)?;
        pos("picard.tol", self.picard.tol)?;
        if !(self.picard.relaxation > 0.0 && self.picard.relaxation <= 1.0) {
            return Err(Error::out_of_range(
                "picard.relaxation",
                self.picard.relaxation,
                "in (0, 1]",
            ));
        }
        if self.picard.max_iterations == 0 {
            return Err(Error::out_of_range("picard.max_iterations", 0, "≥ 1"));
        }
        if !(2..=2000).contains(&self.elements) {
            return Err(Error::out_of_range(
                "elements",
                self.elements,
                "in 2..=2000",
            ));
        }
        if !(1..=100_000).contains(&self.steps) {
            return Err(Error::out_of_range("steps", self.steps, "in 1..=100000"));
        }
        if !(1..=5).contains(&self.layers) {
            return Err(Error::out_of_range("layers", self.layers, "in 1..=5"));
        }
        if self.punch.radius >= self.die.opening_radius {
            return Err(Error::out_of_range(
                "punch.radius",
                self.punch.radius,
                format!("< die.opening_radius = {}", self.die.opening_radius),
            ));
        }
        if self.die.opening_radius - self.punch.radius < self.thickness {
            return Err(Error::out_of_range(
                "the die clearance (die.opening_radius − punch.radius)",
                self.die.opening_radius - self.punch.radius,
                format!("≥ the thickness = {}", self.thickness),
            ));
        }
        if self.blank_radius <= self.die.opening_radius {
            return Err(Error::out_of_range(
                "blank_radius",
                self.blank_radius,
                format!("> die.opening_radius = {}", self.die.opening_radius),
            ));
        }
        for &s in &self.snapshots {
            nonneg("snapshots entry", s)?;
        }
        self.material.validate()
    }
}

/// The contact rule: the classical constant penalty, the paper's Eq. 28–29 in two readings, or
/// the exact δ-targeting `condensed` rule. δ is a length (in); the solver uses δ/Δt in
/// velocity units.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "rule", rename_all = "kebab-case")]
pub enum ContactRule {
    /// One ε (ton-force·s/in) for every active contact DOF (Eq. 9).
    Classical {
        /// ε.
        eps: f64,
    },
    /// Eq. 28–29 literally, per contact DOF and per Picard iteration: the force estimate is
    /// `|K̄û − q̄|` with every unconstrained velocity taken as zero. On a stationary tool
    /// (û = 0) with no load of its own (q̄ = 0) it gives `ε = −(K̄δ1)/δ < 0`: the node is
    /// clipped and released while it penetrates (a known failure, kept for comparison).
    #[serde(alias = "paper")]
    PaperLiteral {
        /// Allowed penetration δ (in).
        delta: f64,
    },
    /// Eq. 28–29 on the contact rows' current residual: the force estimate is
    /// `|(K ũ − q)_c|`, `ũ` = the current Picard iterate with the contact DOFs at û
    /// (`crate::strategy::paper::eq28_at`), so a node on a stationary tool gets the force it
    /// carries. Reduces to the literal reading when the iterate is zero; at a converged
    /// Picard step every compressive contact ends at penetration δ. The default `adaptive`
    /// run.
    PaperResidual {
        /// Allowed penetration δ (in).
        delta: f64,
    },
    /// Exact δ-targeting via `S = DᵀK⁻¹D` (crate strategy `condensed`).
    Condensed {
        /// Allowed penetration δ (in).
        delta: f64,
    },
}

impl ContactRule {
    /// Short name: `classical`, `paper-literal`, `paper-residual`, `condensed`.
    pub fn name(&self) -> &'static str {
        match self {
            ContactRule::Classical { .. } => "classical",
            ContactRule::PaperLiteral { .. } => "paper-literal",
            ContactRule::PaperResidual { .. } => "paper-residual",
            ContactRule::Condensed { .. } => crate::strategy::condensed::STRATEGY.name,
        }
    }

    /// δ (in) for the adaptive rules.
    pub fn delta(&self) -> Option<f64> {
        match *self {
            ContactRule::Classical { .. } => None,
            ContactRule::PaperLiteral { delta }
            | ContactRule::PaperResidual { delta }
            | ContactRule::Condensed { delta } => Some(delta),
        }
    }

    /// Checks ε > 0 or δ > 0.
    pub fn validate(&self) -> Result<()> {
        let (what, v) = match *self {
            ContactRule::Classical { eps } => ("penalty ε", eps),
            _ => ("δ", self.delta().unwrap_or(f64::NAN)),
        };
        Error::positive(what, v).map(|_| ())
    }
}
