//! The strategy registry: one [`Strategy`] descriptor per rule, declared in the rule's own
//! file, and one list of them ([`BUILT_IN`]). Everything else — the CLI's `--method` choices
//! and their help, [`Method::from_name`](super::Method::from_name), the sweep's job lists and
//! rows, figure colours and legends, `engine_scale`'s methods — derives from the descriptors.
//!
//! A descriptor holds the rule's numerics (knob, K⁻¹, δ guarantee, ties, force tolerance,
//! `solve`) and, apart, its presentation ([`Look`]: labels, colour, glyph); each declares only
//! what differs from [`Strategy::BASE`] and [`Look::BASE`].
//!
//! A rule from outside the crate is a `static` [`Strategy`] whose `solve` uses the public
//! drivers ([`fixed_point`](super::fixed_point), [`fixed_energy`](super::fixed_energy),
//! [`per_active`](super::per_active)), made known once with [`register`]; from then on the
//! sweep, `Method::from_name` and the figures treat it like a built-in rule
//! (`examples/custom_rule.rs`).
//!
//! Registration is process-global (a lock-guarded list; rules are never removed), so that the
//! sweep's worker threads and the figure code see the same set without a registry handle
//! threaded through every call.

use super::{Context, Method, Solution};
use crate::error::{Error, Result};
use std::sync::RwLock;

/// What a strategy's knob is: the value a user sets, and how the sweep varies it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Knob {
    /// No knob (exact methods).
    None,
    /// A penalty ε (stiffness units): the sweep's ε grid (`--eps`).
    Eps,
    /// A dimensionless factor f: the sweep's `--factors`.
    Factor,
    /// An allowed penetration δ (units of u): the sweep's `--deltas` / `--deltas-rel`.
    Delta,
    /// A penalty ε and a penetration tolerance (and an adaptive switch): the sweep runs it with
    /// tol = each δ, ε = the geometric mean of K's constrained diagonal, adaptive.
    EpsTol,
}

/// The symbol of each knob value in messages ([`crate::Error::MissingKnob`],
/// [`crate::Error::NotPositive`]); command-line layers map them to their flags.
pub mod symbol {
    /// The penalty ε.
    pub const EPS: &str = "ε";
    /// The factor f of `scaled`.
    pub const FACTOR: &str = "the factor f";
    /// The allowed penetration δ.
    pub const DELTA: &str = "δ";
    /// The penetration tolerance of `augmented`.
    pub const TOL: &str = "the tolerance";
}

/// The point marker of a strategy in every figure (a second cue beside its colour, so that
/// coinciding curves stay distinguishable and figures survive greyscale printing).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Glyph {
    /// Filled circle.
    #[default]
    Circle,
    /// Filled square.
    Square,
    /// Filled triangle, apex up.
    Triangle,
    /// Filled triangle, apex down.
    TriangleDown,
    /// Filled diamond.
    Diamond,
    /// Filled ×.
    Cross,
    /// Filled +.
    Plus,
    /// Filled pentagon.
    Pentagon,
    /// Filled five-pointed star.
    Star,
}

/// Everything about one strategy, declared in its own file.
#[derive(Debug)]
pub struct Strategy {
    /// The name: `--method NAME`, the `method` column of every row, JSON `"method"`. Unique.
    pub name: &'static str,
    /// One line for `--help` and docs tables.
    pub summary: &'static str,
    /// The knob.
    pub knob: Knob,
    /// Whether its solves need K⁻¹ (a nonsingular K): those that start from u0 = K⁻¹q or use
    /// S = DᵀK⁻¹D.
    pub needs_k_inverse: bool,
    /// Whether it guarantees every penetration ≤ δ (the δ-targeting rules).
    pub targets_delta: bool,
    /// Whether it handles bilateral ties (`u[d] = û`); studies whose scenes have ties (the
    /// sweep's default families, `runtime_vs_error`) leave the others out of their defaults.
    pub bilateral: bool,
    /// Relative force mismatch at which force control ([`super::force_control`]) accepts its
    /// solution: [`super::force_control::FORCE_TOL`] for a rule whose solution is exact for its
    /// penalties, coarser where the solution is an optimiser's output (`optimal`).
    pub force_tol: f64,
    /// Runs it: `method` carries this descriptor and the knob values it declared.
    pub solve: fn(Context, &Method) -> Result<Solution>,
    /// How figures and warnings show it (nothing here changes a number).
    pub look: Look,
}

/// How figures and warnings show a strategy: its presentation, apart from its numerics.
#[derive(Clone, Copy, Debug)]
pub struct Look {
    /// Legend text in every figure (`""`: the name).
    pub label: &'static str,
    /// The rule as named in warnings, e.g. `paper (Eq. 28)` (`""`: the label).
    pub rule_label: &'static str,
    /// Palette index of its colour in every figure (`plot::PALETTE`, taken modulo its length).
    pub colour: usize,
    /// Its point marker in every figure.
    pub glyph: Glyph,
}

impl Look {
    /// The defaults a strategy's look starts from (`..Look::BASE`): labels from the name, the
    /// palette's grey, a circle.
    pub const BASE: Look = Look {
        label: "",
        rule_label: "",
        colour: 7,
        glyph: Glyph::Circle,
    };
}

/// [`Strategy::BASE`]'s solve: an error naming the strategy that declared none.
fn undeclared(_: Context, m: &Method) -> Result<Solution> {
    Err(Error::unsupported(
        format!("strategy '{}'", m.strategy().name),
        "a solve (its declaration has none)",
    ))
}

impl Strategy {
    /// The defaults every strategy starts from (`..Strategy::BASE`): no knob, K⁻¹ not needed,
    /// no δ guarantee, bilateral ties handled, force control at
    /// [`super::force_control::FORCE_TOL`], the default [`Look`]; `name`, `summary` and
    /// `solve` are each strategy's own.
    pub const BASE: Strategy = Strategy {
        name: "",
        summary: "",
        knob: Knob::None,
        needs_k_inverse: false,
        targets_delta: false,
        bilateral: true,
        force_tol: super::force_control::FORCE_TOL,
        solve: undeclared,
        look: Look::BASE,
    };

    /// Whether this is the strategy named `name`.
    pub fn is(&self, name: &str) -> bool {
        self.name == name
    }

    /// Legend text in every figure: [`Look::label`], else the name.
    pub fn label(&self) -> &'static str {
        match self.look.label {
            "" => self.name,
            l => l,
        }
    }

    /// The rule as named in warnings: [`Look::rule_label`], else [`Strategy::label`].
    pub fn rule_label(&self) -> &'static str {
        match self.look.rule_label {
            "" => self.label(),
            l => l,
        }
    }
}

/// The built-in strategies, in their order in tables, `--help` and the palette.
pub static BUILT_IN: [&Strategy; 9] = [
    &super::constant::STRATEGY,
    &super::scaled::STRATEGY,
    &super::spring::STRATEGY,
    &super::paper::STRATEGY,
    &super::condensed::STRATEGY,
    &super::lagrange::STRATEGY,
    &super::augmented::STRATEGY,
    &super::optimal::STRATEGY,
    &super::barrier::STRATEGY,
];

static REGISTERED: RwLock<Vec<&'static Strategy>> = RwLock::new(Vec::new());

/// Makes a strategy from outside the crate known to [`find`], [`all`], the sweep and the
/// figures. Registering the same descriptor again is a no-op; another strategy with a taken
/// name, an empty name or one with characters other than `a–z`, `0–9`, `-`, `_` is an error.
pub fn register(s: &'static Strategy) -> Result<()> {
    if s.name.is_empty()
        || !s
            .name
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-' || c == '_')
    {
        return Err(Error::out_of_range(
            "strategy name",
            format!("'{}'", s.name),
            "non-empty and use only a-z, 0-9, '-' and '_'",
        ));
    }
    let mut list = REGISTERED.write().unwrap_or_else(|e| e.into_inner());
    match all_in(&list).into_iter().find(|t| t.name == s.name) {
        Some(t) if std::ptr::eq(t, s) => Ok(()),
        Some(_) => Err(Error::duplicate(
            "strategy name (already registered)",
            format!("'{}'", s.name),
        )),
        None => {
            list.push(s);
            Ok(())
        }
    }
}

fn all_in(registered: &[&'static Strategy]) -> Vec<&'static Strategy> {
    BUILT_IN
        .iter()
        .copied()
        .chain(registered.iter().copied())
        .collect()
}

/// Every known strategy: the built-in ones, then the registered ones in registration order.
pub fn all() -> Vec<&'static Strategy> {
    all_in(&REGISTERED.read().unwrap_or_else(|e| e.into_inner()))
}

/// Their names, in the order of [`all`].
pub fn names() -> Vec<&'static str> {
    all().iter().map(|s| s.name).collect()
}

/// The strategy named `name`.
pub fn find(name: &str) -> Option<&'static Strategy> {
    all().into_iter().find(|s| s.name == name)
}

/// The strategy named `name`, or an error listing the valid names.
pub fn lookup(name: &str) -> Result<&'static Strategy> {
    find(name).ok_or_else(|| Error::unknown("method", name, &names(), ""))
}

/// The strategies named, each looked up with [`lookup`] (the first unknown name is the error).
pub fn lookup_all<S: AsRef<str>>(names: &[S]) -> Result<Vec<&'static Strategy>> {
    names.iter().map(|n| lookup(n.as_ref().trim())).collect()
}

/// Reads strategies by name, the inverse of [`serialize_names`]
/// (`#[serde(deserialize_with = "crate::strategy::registry::deserialize_names")]`): an unknown
/// name is an error naming it and the valid ones.
pub fn deserialize_names<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> std::result::Result<Vec<&'static Strategy>, D::Error> {
    let names = <Vec<String> as serde::Deserialize>::deserialize(d)?;
    lookup_all(&names).map_err(|e| serde::de::Error::custom(e.bare_message()))
}

/// Writes strategies by name: a study's configuration holds `&'static Strategy` (looked up
/// once, where the names enter) and its manifest lists the names
/// (`#[serde(serialize_with = "crate::strategy::registry::serialize_names")]`).
pub fn serialize_names<S: serde::Serializer>(
    v: &[&'static Strategy],
    s: S,
) -> std::result::Result<S::Ok, S::Error> {
    s.collect_seq(v.iter().map(|x| x.name))
}

/// The δ-driven rules drawn per δ in the sweep's figures: every strategy with a δ knob except
/// `optimal`, which is drawn as a frontier.
pub fn delta_rules() -> Vec<&'static Strategy> {
    all()
        .into_iter()
        .filter(|s| s.knob == Knob::Delta && !std::ptr::eq(*s, &super::optimal::STRATEGY))
        .collect()
}

/// The clap parser of a strategy name (`--method`, `--methods`): the names of [`all`] at the
/// time the command line is parsed, each with its summary in `--help`, and the list of valid
/// values in the error message.
#[cfg(feature = "cli")]
pub fn method_parser() -> clap::builder::PossibleValuesParser {
    method_parser_of(&all())
}

/// [`method_parser`] restricted to `strategies` (a study that runs only some of them lists
/// only those in `--help` and in its error message).
#[cfg(feature = "cli")]
pub fn method_parser_of(strategies: &[&'static Strategy]) -> clap::builder::PossibleValuesParser {
    clap::builder::PossibleValuesParser::new(
        strategies
            .iter()
            .map(|s| clap::builder::PossibleValue::new(s.name).help(s.summary)),
    )
}
