//! Id newtypes with a prefixed display form (`job_12`), so signatures never take a bare integer.

use std::fmt;
use std::str::FromStr;

macro_rules! define_id {
    ($(#[$doc:meta])* $name:ident, $prefix:literal) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
        pub struct $name(pub i64);

        impl $name {
            /// The display prefix, including the underscore.
            pub const PREFIX: &'static str = $prefix;
        }

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(f, "{}{}", Self::PREFIX, self.0)
            }
        }

        impl FromStr for $name {
            type Err = crate::QueueError;

            /// Parses the display form (`job_12`); a bare number is refused.
            fn from_str(s: &str) -> Result<Self, Self::Err> {
                s.strip_prefix(Self::PREFIX)
                    .and_then(|n| n.parse::<i64>().ok())
                    .filter(|n| *n > 0)
                    .map(Self)
                    .ok_or_else(|| {
                        crate::QueueError::Invalid(format!("expected an id like {}1, got {s:?}", Self::PREFIX))
                    })
            }
        }
    };
}

define_id!(
    /// A tenant: the owner of API keys, assets and jobs.
    TenantId,
    "tenant_"
);
define_id!(
    /// An asset: one distinct content (by digest) of one tenant.
    AssetId,
    "asset_"
);
define_id!(
    /// A job: one run of the stage graph on one asset.
    JobId,
    "job_"
);
define_id!(
    /// A stage run: one stage of one job, claimed, retried and fenced as a unit.
    StageRunId,
    "run_"
);

/// The identity of one worker process, fresh at every start (a UUID at boot, not a host name),
/// recorded on the runs it claims.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct WorkerId(pub String);

impl fmt::Display for WorkerId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_round_trip_through_their_display_form() {
        let id = JobId(42);
        assert_eq!(id.to_string(), "job_42");
        assert_eq!("job_42".parse::<JobId>().ok(), Some(id));
    }

    #[test]
    fn ids_refuse_other_prefixes_and_bare_numbers() {
        assert!("asset_42".parse::<JobId>().is_err());
        assert!("42".parse::<JobId>().is_err());
        assert!("job_-1".parse::<JobId>().is_err());
        assert!("job_".parse::<JobId>().is_err());
    }
}
