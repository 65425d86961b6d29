use serde::{Deserialize, Serialize};

/// Where a value came from. Every estimated value in an asset record carries one.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Provenance {
    /// Read from the input asset itself (for example a URDF joint or a glTF node name).
    Input {
        /// What in the input the value was read from.
        detail: String,
    },
    /// Produced by a model or service provider (an LVLM, UniPhysGen, or a built-in stand-in).
    Provider {
        /// Provider name, e.g. `builtin-grounder` or `openai:gpt-5`.
        name: String,
        /// Provider version or model id.
        version: String,
    },
    /// Derived by a deterministic rule from other values (e.g. mass = density x volume).
    Rule {
        /// Rule name, e.g. `mass_from_density_and_volume`.
        name: String,
    },
    /// A default used because nothing better was known.
    Default {
        /// Why the default was used.
        reason: String,
    },
}

impl Provenance {
    /// Builds a [`Provenance::Rule`].
    #[must_use]
    pub fn rule(name: impl Into<String>) -> Self {
        Self::Rule { name: name.into() }
    }

    /// Builds a [`Provenance::Default`].
    #[must_use]
    pub fn default_because(reason: impl Into<String>) -> Self {
        Self::Default {
            reason: reason.into(),
        }
    }

    /// Builds a [`Provenance::Input`].
    #[must_use]
    pub fn input(detail: impl Into<String>) -> Self {
        Self::Input {
            detail: detail.into(),
        }
    }

    /// Builds a [`Provenance::Provider`].
    #[must_use]
    pub fn provider(name: impl Into<String>, version: impl Into<String>) -> Self {
        Self::Provider {
            name: name.into(),
            version: version.into(),
        }
    }

    /// Short label for reports: `input`, `provider:<name>`, `rule:<name>` or `default`.
    #[must_use]
    pub fn label(&self) -> String {
        match self {
            Self::Input { .. } => "input".to_owned(),
            Self::Provider { name, .. } => format!("provider:{name}"),
            Self::Rule { name } => format!("rule:{name}"),
            Self::Default { .. } => "default".to_owned(),
        }
    }
}

/// A value with its plausible range and its provenance.
///
/// `low`/`high` bound the value when the producer knows a range (a material prior, a model's
/// confidence interval); they are `None` when it does not.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Estimate<T> {
    /// The value used downstream.
    pub value: T,
    /// Lower end of the plausible range, if known.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub low: Option<T>,
    /// Upper end of the plausible range, if known.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub high: Option<T>,
    /// Who or what produced the value.
    pub provenance: Provenance,
}

impl<T> Estimate<T> {
    /// An estimate without a range.
    pub fn new(value: T, provenance: Provenance) -> Self {
        Self {
            value,
            low: None,
            high: None,
            provenance,
        }
    }

    /// An estimate with a plausible range `[low, high]`.
    pub fn with_range(value: T, low: T, high: T, provenance: Provenance) -> Self {
        Self {
            value,
            low: Some(low),
            high: Some(high),
            provenance,
        }
    }
}
