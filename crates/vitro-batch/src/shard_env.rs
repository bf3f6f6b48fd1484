//! A shard from the environment of a cluster's job array, for `vitro batch` without
//! `--shard`: each task of a Slurm job array, or each pod of a Kubernetes Indexed Job, makes
//! its own share of the runs, and `vitro merge` joins the shards.
//!
//! - Slurm (`sbatch --array=0-3`): `SLURM_ARRAY_TASK_ID` and `SLURM_ARRAY_TASK_COUNT`, with
//!   `SLURM_ARRAY_TASK_MIN` subtracted (an array `1-4` makes shards 0 to 3). An array with a
//!   step (`0-15:4`) is refused: its ids do not number the shards.
//! - Kubernetes Indexed Jobs: `JOB_COMPLETION_INDEX`, with the number of completions in
//!   `VITRO_SHARD_COUNT` (Kubernetes does not export it; set it in the pod template).
//!
//! ```
//! use vitro_batch::design::Shard;
//! use vitro_batch::shard_env::shard_from_env;
//! let env = |k: &str| match k {
//!     "SLURM_ARRAY_TASK_ID" => Some("3".to_string()),
//!     "SLURM_ARRAY_TASK_COUNT" => Some("4".to_string()),
//!     "SLURM_ARRAY_TASK_MIN" => Some("1".to_string()),
//!     "SLURM_ARRAY_JOB_ID" => Some("812".to_string()),
//!     _ => None,
//! };
//! let (shard, from) = shard_from_env(env).unwrap().unwrap();
//! assert_eq!(shard, Shard { index: 2, count: 4 });
//! assert_eq!(from, "Slurm job array 812, task 3 (SLURM_ARRAY_TASK_ID)");
//! assert_eq!(shard_from_env(|_| None).unwrap(), None);
//! ```

use crate::design::Shard;

/// Why the environment names no usable shard.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ShardEnvError {
    /// A variable holds something else than expected.
    #[error("environment variable {var}={value:?}: expected {expected}")]
    Bad {
        /// The variable.
        var: &'static str,
        /// Its value.
        value: String,
        /// What it should hold.
        expected: &'static str,
    },
    /// One variable of a pair is set, the other is not.
    #[error("environment variable {present} is set but {missing} is not ({why})")]
    Missing {
        /// The variable that is set.
        present: &'static str,
        /// The one that is not.
        missing: &'static str,
        /// Where it should come from.
        why: &'static str,
    },
}

fn number(
    var: &'static str,
    get: &impl Fn(&str) -> Option<String>,
    expected: &'static str,
) -> Result<Option<u64>, ShardEnvError> {
    match get(var) {
        None => Ok(None),
        Some(v) => v
            .trim()
            .parse::<u64>()
            .map(Some)
            .map_err(|_| ShardEnvError::Bad {
                var,
                value: v,
                expected,
            }),
    }
}

/// The shard the environment names (with a line saying where it came from), or `None` when
/// no job array is running this process. `get` reads a variable (`std::env::var(k).ok()`).
pub fn shard_from_env(
    get: impl Fn(&str) -> Option<String>,
) -> Result<Option<(Shard, String)>, ShardEnvError> {
    const ID: &str = "SLURM_ARRAY_TASK_ID";
    const COUNT: &str = "SLURM_ARRAY_TASK_COUNT";
    const K8S_INDEX: &str = "JOB_COMPLETION_INDEX";
    const K8S_COUNT: &str = "VITRO_SHARD_COUNT";
    let positive = "a positive whole number";
    let whole = "a whole number";
    if let Some(id) = number(ID, &get, whole)? {
        let count =
            number(COUNT, &get, positive)?
                .filter(|&c| c > 0)
                .ok_or(ShardEnvError::Missing {
                    present: ID,
                    missing: COUNT,
                    why: "Slurm sets both in a job array",
                })?;
        if let Some(step) = number("SLURM_ARRAY_TASK_STEP", &get, positive)?
            && step != 1
        {
            return Err(ShardEnvError::Bad {
                var: "SLURM_ARRAY_TASK_STEP",
                value: step.to_string(),
                expected: "1 (an array without a step, e.g. --array=0-3)",
            });
        }
        let min = number("SLURM_ARRAY_TASK_MIN", &get, whole)?.unwrap_or(0);
        let index = id
            .checked_sub(min)
            .filter(|&i| i < count)
            .ok_or(ShardEnvError::Bad {
                var: ID,
                value: id.to_string(),
                expected: "a task id from SLURM_ARRAY_TASK_MIN on, fewer than SLURM_ARRAY_TASK_COUNT past it",
            })?;
        let job = get("SLURM_ARRAY_JOB_ID").map_or(String::new(), |j| format!(" {}", j.trim()));
        let from = format!("Slurm job array{job}, task {id} ({ID})");
        return Ok(Some((Shard { index, count }, from)));
    }
    if let Some(index) = number(K8S_INDEX, &get, whole)? {
        let count = number(K8S_COUNT, &get, positive)?
            .filter(|&c| c > 0)
            .ok_or(ShardEnvError::Missing {
                present: K8S_INDEX,
                missing: K8S_COUNT,
                why: "set it to the Indexed Job's completions in the pod template",
            })?;
        if index >= count {
            return Err(ShardEnvError::Bad {
                var: K8S_INDEX,
                value: index.to_string(),
                expected: "an index below VITRO_SHARD_COUNT",
            });
        }
        let from = format!("Kubernetes Indexed Job, index {index} ({K8S_INDEX})");
        return Ok(Some((Shard { index, count }, from)));
    }
    Ok(None)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn env<'a>(vars: &'a [(&'a str, &'a str)]) -> impl Fn(&str) -> Option<String> + 'a {
        move |k| {
            vars.iter()
                .find(|(n, _)| *n == k)
                .map(|(_, v)| v.to_string())
        }
    }

    #[test]
    fn slurm_arrays_from_zero_and_from_one() {
        let zero = [
            ("SLURM_ARRAY_TASK_ID", "0"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
        ];
        let (s, from) = shard_from_env(env(&zero)).unwrap().unwrap();
        assert_eq!(s, Shard { index: 0, count: 4 });
        assert_eq!(from, "Slurm job array, task 0 (SLURM_ARRAY_TASK_ID)");
        let one = [
            ("SLURM_ARRAY_TASK_ID", "4"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
            ("SLURM_ARRAY_TASK_MIN", "1"),
        ];
        assert_eq!(
            shard_from_env(env(&one)).unwrap().unwrap().0,
            Shard { index: 3, count: 4 }
        );
    }

    #[test]
    fn bad_or_partial_arrays_are_errors() {
        let no_count = [("SLURM_ARRAY_TASK_ID", "2")];
        assert!(matches!(
            shard_from_env(env(&no_count)),
            Err(ShardEnvError::Missing { .. })
        ));
        let stepped = [
            ("SLURM_ARRAY_TASK_ID", "4"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
            ("SLURM_ARRAY_TASK_STEP", "4"),
        ];
        assert!(shard_from_env(env(&stepped)).is_err());
        let past = [
            ("SLURM_ARRAY_TASK_ID", "4"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
        ];
        let e = shard_from_env(env(&past)).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("environment variable SLURM_ARRAY_TASK_ID=\"4\"")
        );
        let text = [
            ("SLURM_ARRAY_TASK_ID", "x"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
        ];
        assert!(shard_from_env(env(&text)).is_err());
    }

    #[test]
    fn kubernetes_indexed_jobs_need_the_count() {
        let k = [("JOB_COMPLETION_INDEX", "2"), ("VITRO_SHARD_COUNT", "3")];
        assert_eq!(
            shard_from_env(env(&k)).unwrap().unwrap().0,
            Shard { index: 2, count: 3 }
        );
        let alone = [("JOB_COMPLETION_INDEX", "2")];
        assert!(matches!(
            shard_from_env(env(&alone)),
            Err(ShardEnvError::Missing { .. })
        ));
        let past = [("JOB_COMPLETION_INDEX", "3"), ("VITRO_SHARD_COUNT", "3")];
        assert!(shard_from_env(env(&past)).is_err());
    }
}
