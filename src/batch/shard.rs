//! Shards: which part of a batch one task does. Shard `i` of `n` owns the
//! items `k` with `k % n == i` (frames, benchmark jobs), so shards are
//! balanced, disjoint, cover everything, and need no coordination: each task
//! computes its part from `i` and `n` alone.
//!
//! `i` and `n` are given as `i/n`, or read from a scheduler's environment
//! ([`Shard::from_env`]): a Slurm job array or a Kubernetes Indexed Job.

use serde::{Deserialize, Serialize};
use std::fmt;

/// Slurm: this task's array index.
pub const SLURM_ID: &str = "SLURM_ARRAY_TASK_ID";
/// Slurm: the number of tasks in the array.
pub const SLURM_COUNT: &str = "SLURM_ARRAY_TASK_COUNT";
/// Slurm: the array's lowest index.
pub const SLURM_MIN: &str = "SLURM_ARRAY_TASK_MIN";
/// Slurm: the array's highest index.
pub const SLURM_MAX: &str = "SLURM_ARRAY_TASK_MAX";
/// Slurm: the array's index step (`--array=0-15:2` has 2).
pub const SLURM_STEP: &str = "SLURM_ARRAY_TASK_STEP";
/// Kubernetes Indexed Jobs: this pod's completion index (0 … completions-1).
pub const K8S_INDEX: &str = "JOB_COMPLETION_INDEX";
/// The shard count for schedulers that do not publish one (Kubernetes sets
/// only the index): set it to the Job's `completions`.
pub const COUNT_VAR: &str = "ISOTRACE_SHARD_COUNT";

/// Shard `index` of `count` (0 ≤ index < count). Read from JSON (a
/// manifest's `shard`) it is checked like `i/n`: a count of 0 or an index
/// at or past the count is an error, never a division by zero later.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(try_from = "ShardFields")]
pub struct Shard {
    /// Which shard, from 0.
    pub index: usize,
    /// How many shards.
    pub count: usize,
}

impl Shard {
    /// The whole batch as one shard (0/1).
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// Shard `index` of `count`, or `None` unless 0 ≤ index < count.
    pub fn new(index: usize, count: usize) -> Option<Shard> {
        (index < count).then_some(Shard { index, count })
    }

    /// Parses `i/n` (spaces around the numbers allowed).
    pub fn parse(s: &str) -> Result<Shard, ShardError> {
        let bad = || ShardError::Syntax { text: s.to_string() };
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let (i, n) = (i.trim().parse().map_err(|_| bad())?, n.trim().parse().map_err(|_| bad())?);
        Shard::new(i, n).ok_or_else(bad)
    }

    /// Whether item `k` of the batch belongs to this shard (never, for a
    /// count of 0 built in code: no shard is empty by division).
    pub fn contains(self, k: usize) -> bool {
        k.checked_rem(self.count) == Some(self.index)
    }

    /// The items of this shard among `0 … n-1`, in order, made one at a
    /// time (a million frames need no list).
    pub fn items(self, n: usize) -> impl Iterator<Item = usize> {
        let end = if self.count == 0 { self.index } else { n };
        (self.index..end).step_by(self.count.max(1))
    }

    /// Reads the shard from a scheduler's environment through `lookup`
    /// (`std::env::var(..).ok()` in the CLI, a table in tests):
    ///
    /// - Slurm job arrays: [`SLURM_ID`] with [`SLURM_COUNT`], or with
    ///   [`SLURM_MIN`] and [`SLURM_MAX`] (the index is then `ID - MIN`, so
    ///   `--array=1-16` works too). The array must be a contiguous range
    ///   (step 1): a shard is `k % n == i`, and a gap would lose its items.
    /// - Kubernetes Indexed Jobs: [`K8S_INDEX`], with the count from `given`
    ///   (the command line) or else [`COUNT_VAR`].
    ///
    /// `given` is an explicit count and where it came from (for messages);
    /// with Slurm it must agree with the array. Any disagreement, a value
    /// that is not a number, or no scheduler at all is an error that names
    /// the variables, so a misconfigured task never renders someone else's
    /// part.
    pub fn from_env(lookup: impl Fn(&str) -> Option<String>, given: Option<GivenCount>) -> Result<Resolved, ShardError> {
        let var = |name: &'static str| lookup(name).map(|v| (name, v));
        let num = |(name, value): (&'static str, String)| -> Result<usize, ShardError> {
            value.trim().parse::<usize>().map_err(|_| ShardError::NotANumber { var: name, value })
        };
        let given = match given {
            Some(g) => Some(g),
            None => var(COUNT_VAR).map(|v| num(v.clone()).map(|n| GivenCount { count: n, source: format!("{}={}", v.0, v.1) })).transpose()?,
        };
        match (var(SLURM_ID), var(K8S_INDEX)) {
            (None, None) => Err(ShardError::NoScheduler),
            (Some(s), Some(k)) => Err(ShardError::TwoSchedulers { slurm: s.1, kubernetes: k.1 }),
            (Some(id), None) => slurm(id, &var, &num, given),
            (None, Some(ix)) => {
                let index = num(ix.clone())?;
                let Some(g) = given else { return Err(ShardError::NoCount { index: ix.1 }) };
                let shard = checked(index, &format!("{}={}", ix.0, ix.1), &g)?;
                Ok(Resolved { shard, source: format!("{}={} and {}", ix.0, ix.1, g.source) })
            }
        }
    }
}

/// The Slurm half of [`Shard::from_env`].
fn slurm(
    id: (&'static str, String),
    var: &dyn Fn(&'static str) -> Option<(&'static str, String)>,
    num: &dyn Fn((&'static str, String)) -> Result<usize, ShardError>,
    given: Option<GivenCount>,
) -> Result<Resolved, ShardError> {
    let task = num(id.clone())?;
    let show = |v: &(&str, String)| format!("{}={}", v.0, v.1);
    if let Some(step) = var(SLURM_STEP)
        && num(step.clone())? != 1
    {
        return Err(ShardError::Inconsistent { detail: format!("{}: the array must be a range with step 1", show(&step)) });
    }
    // The zero-based index and the count, from MIN and MAX when they are set.
    let from_range = match (var(SLURM_MIN), var(SLURM_MAX)) {
        (Some(lo), Some(hi)) => {
            let (min, max) = (num(lo.clone())?, num(hi.clone())?);
            if !(min <= task && task <= max) {
                return Err(ShardError::Inconsistent { detail: format!("{} is outside {}..{}", show(&id), show(&lo), show(&hi)) });
            }
            Some((task - min, max - min + 1, format!("{}, {} and {}", show(&id), show(&lo), show(&hi))))
        }
        _ => None,
    };
    let (shard, source) = match (from_range, var(SLURM_COUNT)) {
        (Some((i, n, src)), Some(c)) => {
            if num(c.clone())? != n {
                return Err(ShardError::Inconsistent { detail: format!("{} but {src} hold {n} tasks: the array must be a range with step 1", show(&c)) });
            }
            (Shard { index: i, count: n }, src)
        }
        (Some((i, n, src)), None) => (Shard { index: i, count: n }, src),
        (None, Some(c)) => {
            let count = GivenCount { count: num(c.clone())?, source: show(&c) };
            (checked(task, &show(&id), &count)?, format!("{} and {}", show(&id), show(&c)))
        }
        (None, None) => match &given {
            Some(g) => (checked(task, &show(&id), g)?, format!("{} and {}", show(&id), g.source)),
            None => return Err(ShardError::NoCount { index: id.1 }),
        },
    };
    if let Some(g) = given.filter(|g| g.count != shard.count) {
        return Err(ShardError::Inconsistent { detail: format!("{} but {source} make {} shards", g.source, shard.count) });
    }
    Ok(Resolved { shard, source })
}

/// A shard as JSON holds it, before [`Shard`]'s rule is checked.
#[derive(Deserialize)]
struct ShardFields {
    index: usize,
    count: usize,
}

impl TryFrom<ShardFields> for Shard {
    type Error = String;

    /// The message names the keys (`shard.count`), the JSON path of the one
    /// place a shard is read from: a manifest's `shard`.
    fn try_from(f: ShardFields) -> Result<Shard, String> {
        if f.count == 0 {
            return Err("shard.count is 0: a shard count must be at least 1".into());
        }
        Shard::new(f.index, f.count).ok_or_else(|| format!("shard.index is {} but shard.count is {}: the index must be below the count", f.index, f.count))
    }
}

/// `index` of `count`, or an error naming where both came from.
fn checked(index: usize, index_source: &str, count: &GivenCount) -> Result<Shard, ShardError> {
    if count.count == 0 {
        return Err(ShardError::Inconsistent { detail: format!("{}: the shard count must be at least 1", count.source) });
    }
    Shard::new(index, count.count).ok_or_else(|| ShardError::Inconsistent {
        detail: format!("{index_source} is not below the shard count {} ({})", count.count, count.source),
    })
}

/// A shard count given explicitly, and where (for messages): the command
/// line's `--shard-count 16`, or `ISOTRACE_SHARD_COUNT=16`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct GivenCount {
    /// The count.
    pub count: usize,
    /// Where it came from, as the user would recognise it.
    pub source: String,
}

/// A shard read from the environment, and the variables it came from (so a
/// task's log says why it did what it did).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Resolved {
    /// The shard.
    pub shard: Shard,
    /// `SLURM_ARRAY_TASK_ID=3 and SLURM_ARRAY_TASK_COUNT=16`, …
    pub source: String,
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// Why no shard could be determined.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ShardError {
    /// Not `i/n` with 0 ≤ i < n.
    #[error("'{text}': expected i/n with 0 <= i < n, e.g. 0/4")]
    Syntax {
        /// What was given.
        text: String,
    },
    /// No scheduler variable is set.
    #[error(
        "no array task in the environment: neither SLURM_ARRAY_TASK_ID (a Slurm job array) nor JOB_COMPLETION_INDEX (a Kubernetes Indexed Job) is set"
    )]
    NoScheduler,
    /// Both are set: which one is meant is a guess.
    #[error("both SLURM_ARRAY_TASK_ID={slurm} and JOB_COMPLETION_INDEX={kubernetes} are set; unset the one that does not belong to this task")]
    TwoSchedulers {
        /// The Slurm index.
        slurm: String,
        /// The Kubernetes index.
        kubernetes: String,
    },
    /// A variable that is not a non-negative integer.
    #[error("{var}='{value}' is not a non-negative integer")]
    NotANumber {
        /// The variable.
        var: &'static str,
        /// Its value.
        value: String,
    },
    /// An index without any count.
    #[error(
        "the task index {index} is set but the shard count is not: set SLURM_ARRAY_TASK_COUNT (or SLURM_ARRAY_TASK_MIN and SLURM_ARRAY_TASK_MAX) for Slurm, or ISOTRACE_SHARD_COUNT to the Job's completions for Kubernetes"
    )]
    NoCount {
        /// The index variable's value.
        index: String,
    },
    /// The variables (or an explicit count) disagree.
    #[error("inconsistent array variables: {detail}")]
    Inconsistent {
        /// Which values disagree, by name.
        detail: String,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    fn env<'a>(vars: &'a [(&'a str, &'a str)]) -> impl Fn(&str) -> Option<String> + 'a {
        move |name| vars.iter().find(|(k, _)| *k == name).map(|(_, v)| v.to_string())
    }

    #[test]
    fn items_are_every_nth_from_the_index() {
        let s = Shard::parse("1/3").unwrap();
        assert_eq!(s.items(8).collect::<Vec<_>>(), [1, 4, 7]);
        assert!(s.contains(4) && !s.contains(5));
        assert_eq!(Shard::ALL.items(3).collect::<Vec<_>>(), [0, 1, 2]);
        assert_eq!(Shard::parse("5/8").unwrap().items(4).count(), 0);
    }

    #[test]
    fn json_shards_follow_the_rule_of_i_over_n() {
        let read = |t: &str| serde_json::from_str::<Shard>(t).map_err(|e| e.to_string());
        assert_eq!(read(r#"{"index": 2, "count": 4}"#), Ok(Shard { index: 2, count: 4 }));
        assert_eq!(read(r#"{"index": 0, "count": 0}"#), Err("shard.count is 0: a shard count must be at least 1".into()));
        assert_eq!(read(r#"{"index": 4, "count": 4}"#), Err("shard.index is 4 but shard.count is 4: the index must be below the count".into()));
        // Built in code with a count of 0, a shard holds nothing instead of dividing by zero.
        let zero = Shard { index: 0, count: 0 };
        assert!(!zero.contains(0) && zero.items(10).next().is_none());
    }

    #[test]
    fn slurm_range_gives_a_zero_based_index() {
        let r = Shard::from_env(env(&[(SLURM_ID, "5"), (SLURM_MIN, "1"), (SLURM_MAX, "16"), (SLURM_COUNT, "16"), (SLURM_STEP, "1")]), None).unwrap();
        assert_eq!(r.shard, Shard { index: 4, count: 16 });
        assert_eq!(r.source, "SLURM_ARRAY_TASK_ID=5, SLURM_ARRAY_TASK_MIN=1 and SLURM_ARRAY_TASK_MAX=16");
        let r = Shard::from_env(env(&[(SLURM_ID, "3"), (SLURM_COUNT, "4")]), None).unwrap();
        assert_eq!((r.shard, r.source.as_str()), (Shard { index: 3, count: 4 }, "SLURM_ARRAY_TASK_ID=3 and SLURM_ARRAY_TASK_COUNT=4"));
    }

    #[test]
    fn kubernetes_takes_the_count_from_the_command_line_or_the_environment() {
        let given = GivenCount { count: 8, source: "--shard-count 8".into() };
        let r = Shard::from_env(env(&[(K8S_INDEX, "7"), (COUNT_VAR, "99")]), Some(given)).unwrap();
        assert_eq!((r.shard, r.source.as_str()), (Shard { index: 7, count: 8 }, "JOB_COMPLETION_INDEX=7 and --shard-count 8"));
        let r = Shard::from_env(env(&[(K8S_INDEX, "2"), (COUNT_VAR, "4")]), None).unwrap();
        assert_eq!(r.shard, Shard { index: 2, count: 4 });
    }

    #[test]
    fn every_missing_or_inconsistent_setting_names_its_variables() {
        let e = |vars: &[(&str, &str)]| Shard::from_env(env(vars), None).unwrap_err().to_string();
        assert_eq!(e(&[]), ShardError::NoScheduler.to_string());
        assert_eq!(e(&[(K8S_INDEX, "2")]), "the task index 2 is set but the shard count is not: set SLURM_ARRAY_TASK_COUNT (or SLURM_ARRAY_TASK_MIN and SLURM_ARRAY_TASK_MAX) for Slurm, or ISOTRACE_SHARD_COUNT to the Job's completions for Kubernetes");
        assert_eq!(e(&[(K8S_INDEX, "4"), (COUNT_VAR, "4")]), "inconsistent array variables: JOB_COMPLETION_INDEX=4 is not below the shard count 4 (ISOTRACE_SHARD_COUNT=4)");
        assert_eq!(e(&[(K8S_INDEX, "x")]), "JOB_COMPLETION_INDEX='x' is not a non-negative integer");
        assert_eq!(e(&[(SLURM_ID, "1"), (K8S_INDEX, "1")]), "both SLURM_ARRAY_TASK_ID=1 and JOB_COMPLETION_INDEX=1 are set; unset the one that does not belong to this task");
        assert_eq!(e(&[(SLURM_ID, "4"), (SLURM_COUNT, "4")]), "inconsistent array variables: SLURM_ARRAY_TASK_ID=4 is not below the shard count 4 (SLURM_ARRAY_TASK_COUNT=4)");
        assert_eq!(e(&[(SLURM_ID, "0"), (SLURM_MIN, "0"), (SLURM_MAX, "15"), (SLURM_COUNT, "8")]), "inconsistent array variables: SLURM_ARRAY_TASK_COUNT=8 but SLURM_ARRAY_TASK_ID=0, SLURM_ARRAY_TASK_MIN=0 and SLURM_ARRAY_TASK_MAX=15 hold 16 tasks: the array must be a range with step 1");
        assert_eq!(e(&[(SLURM_ID, "0"), (SLURM_MIN, "0"), (SLURM_MAX, "15"), (SLURM_STEP, "2")]), "inconsistent array variables: SLURM_ARRAY_TASK_STEP=2: the array must be a range with step 1");
        assert_eq!(e(&[(SLURM_ID, "20"), (SLURM_MIN, "0"), (SLURM_MAX, "15")]), "inconsistent array variables: SLURM_ARRAY_TASK_ID=20 is outside SLURM_ARRAY_TASK_MIN=0..SLURM_ARRAY_TASK_MAX=15");
        assert_eq!(e(&[(SLURM_ID, "2"), (SLURM_COUNT, "4"), (COUNT_VAR, "8")]), "inconsistent array variables: ISOTRACE_SHARD_COUNT=8 but SLURM_ARRAY_TASK_ID=2 and SLURM_ARRAY_TASK_COUNT=4 make 4 shards");
        assert_eq!(e(&[(SLURM_ID, "2")]), "the task index 2 is set but the shard count is not: set SLURM_ARRAY_TASK_COUNT (or SLURM_ARRAY_TASK_MIN and SLURM_ARRAY_TASK_MAX) for Slurm, or ISOTRACE_SHARD_COUNT to the Job's completions for Kubernetes");
    }
}
