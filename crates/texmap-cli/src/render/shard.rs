//! `--shard`: which contiguous slice of a batch's outputs this process renders.
//!
//! A batch is a list of outputs in a fixed order (inputs in the order given, each input's
//! frames in order; see `plan.rs`). `--shard I/N` cuts it into N contiguous slices whose
//! sizes differ by at most one — slice `i` (0-based) is outputs `⌊i·M/N⌋ .. ⌊(i+1)·M/N⌋` of
//! M — and renders slice I, counted **from 1** (`--shard 1/4` … `--shard 4/4`). Slices never
//! overlap and together hold every output once, whatever N; a slice may be empty when N > M.
//!
//! `--shard auto` takes the index from the job engine's environment:
//! - Slurm job arrays: `SLURM_ARRAY_TASK_ID`, less `SLURM_ARRAY_TASK_MIN`, divided by
//!   `SLURM_ARRAY_TASK_STEP` (when set) is the 0-based index; `SLURM_ARRAY_TASK_COUNT` the count.
//! - Kubernetes Indexed Jobs: `JOB_COMPLETION_INDEX` is the 0-based index; the count is
//!   `--shard-count N` (the Job's `completions`), which Kubernetes does not export.
//!
//! `--shard-count` given with Slurm's variables must agree with `SLURM_ARRAY_TASK_COUNT`.

use texmap::Error;

/// One slice of N: `index` is 0-based.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    pub index: u64,
    pub count: u64,
}

impl Shard {
    /// The whole batch.
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// The outputs `start..end` of `total` this slice holds.
    #[must_use]
    pub fn range(self, total: u64) -> std::ops::Range<u64> {
        let at = |i: u64| (u128::from(i) * u128::from(total) / u128::from(self.count)) as u64;
        at(self.index)..at(self.index + 1)
    }

    /// `I/N`, counted from 1 as `--shard` takes it.
    #[must_use]
    pub fn label(self) -> String {
        format!("{}/{}", self.index + 1, self.count)
    }
}

/// `--shard` and `--shard-count` resolved, `env` reading the environment (a parameter so
/// tests can give their own).
///
/// # Errors
/// [`Error::Parameter`], one line: a malformed or out-of-range `I/N`, `auto` with no
/// engine's variables set or Kubernetes' without `--shard-count`, a count that disagrees
/// with Slurm's, `--shard-count` without `--shard auto`.
pub fn resolve(
    shard: Option<&str>,
    shard_count: Option<u64>,
    env: impl Fn(&str) -> Option<String>,
) -> Result<Shard, Error> {
    let Some(spec) = shard else {
        if shard_count.is_some() {
            return Err(Error::parameter(
                "--shard-count: only with --shard auto (the count of a Kubernetes Indexed Job)",
            ));
        }
        return Ok(Shard::ALL);
    };
    if spec == "auto" {
        return from_env(shard_count, env);
    }
    if shard_count.is_some() {
        return Err(Error::parameter(format!(
            "--shard-count: only with --shard auto (--shard {spec} names its count)"
        )));
    }
    let bad = || {
        Error::parameter(format!(
            "--shard {spec}: expected I/N with 1 ≤ I ≤ N (e.g. 2/8; counted from 1), or auto"
        ))
    };
    let (i, n) = spec.split_once('/').ok_or_else(bad)?;
    let (i, n): (u64, u64) = (
        i.trim().parse().map_err(|_| bad())?,
        n.trim().parse().map_err(|_| bad())?,
    );
    if n == 0 || i == 0 || i > n {
        return Err(bad());
    }
    Ok(Shard {
        index: i - 1,
        count: n,
    })
}

fn from_env(
    shard_count: Option<u64>,
    env: impl Fn(&str) -> Option<String>,
) -> Result<Shard, Error> {
    let number = |name: &str| -> Result<Option<u64>, Error> {
        match env(name) {
            None => Ok(None),
            Some(v) if v.trim().is_empty() => Ok(None),
            Some(v) => v.trim().parse().map(Some).map_err(|_| {
                Error::parameter(format!(
                    "--shard auto: {name}={v:?} is not a non-negative whole number"
                ))
            }),
        }
    };
    if shard_count == Some(0) {
        return Err(Error::parameter("--shard-count 0: must be at least 1"));
    }
    if let Some(id) = number("SLURM_ARRAY_TASK_ID")? {
        let min = number("SLURM_ARRAY_TASK_MIN")?.unwrap_or(0);
        let step = number("SLURM_ARRAY_TASK_STEP")?.unwrap_or(1).max(1);
        let count = number("SLURM_ARRAY_TASK_COUNT")?.ok_or_else(|| {
            Error::parameter(
                "--shard auto: SLURM_ARRAY_TASK_ID is set but SLURM_ARRAY_TASK_COUNT is not",
            )
        })?;
        if id < min || (id - min) % step != 0 {
            return Err(Error::parameter(format!(
                "--shard auto: SLURM_ARRAY_TASK_ID={id} is not in the array \
                 (SLURM_ARRAY_TASK_MIN={min}, step {step})"
            )));
        }
        let index = (id - min) / step;
        if let Some(n) = shard_count.filter(|&n| n != count) {
            return Err(Error::parameter(format!(
                "--shard-count {n}: Slurm says SLURM_ARRAY_TASK_COUNT={count}"
            )));
        }
        return checked(index, count, "SLURM_ARRAY_TASK_ID");
    }
    if let Some(index) = number("JOB_COMPLETION_INDEX")? {
        let count = shard_count.ok_or_else(|| {
            Error::parameter(
                "--shard auto: JOB_COMPLETION_INDEX is set (a Kubernetes Indexed Job) but not \
                 --shard-count N (the Job's completions)",
            )
        })?;
        return checked(index, count, "JOB_COMPLETION_INDEX");
    }
    Err(Error::parameter(
        "--shard auto: no job index in the environment (SLURM_ARRAY_TASK_ID for a Slurm job \
         array, JOB_COMPLETION_INDEX for a Kubernetes Indexed Job); give --shard I/N",
    ))
}

fn checked(index: u64, count: u64, name: &str) -> Result<Shard, Error> {
    if count == 0 || index >= count {
        return Err(Error::parameter(format!(
            "--shard auto: {name} gives index {index} (from 0) of {count} shards: out of range"
        )));
    }
    Ok(Shard { index, count })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vars<'a>(v: &'a [(&'a str, &'a str)]) -> impl Fn(&str) -> Option<String> + 'a {
        move |k| v.iter().find(|(n, _)| *n == k).map(|(_, x)| x.to_string())
    }

    #[test]
    fn slices_are_contiguous_and_cover_every_output_once() {
        for total in [0u64, 1, 7, 100, 361] {
            for count in 1..=9 {
                let mut next = 0;
                for index in 0..count {
                    let r = Shard { index, count }.range(total);
                    assert_eq!(r.start, next);
                    assert!(r.end - r.start <= total / count + 1);
                    next = r.end;
                }
                assert_eq!(next, total);
            }
        }
    }

    #[test]
    fn explicit_shards_count_from_one() {
        let s = resolve(Some("2/4"), None, vars(&[])).unwrap();
        assert_eq!(s, Shard { index: 1, count: 4 });
        assert_eq!(s.label(), "2/4");
        for bad in ["3/2", "0/2", "1/0", "a/b", "2", "auto/2"] {
            let e = resolve(Some(bad), None, vars(&[])).unwrap_err().to_string();
            assert!(e.contains("--shard"), "{e}");
        }
        assert!(resolve(None, Some(3), vars(&[])).is_err());
    }

    #[test]
    fn slurm_and_kubernetes_indexes() {
        let slurm = [
            ("SLURM_ARRAY_TASK_ID", "7"),
            ("SLURM_ARRAY_TASK_MIN", "5"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
        ];
        let s = resolve(Some("auto"), None, vars(&slurm)).unwrap();
        assert_eq!(s, Shard { index: 2, count: 4 });
        let stepped = [
            ("SLURM_ARRAY_TASK_ID", "6"),
            ("SLURM_ARRAY_TASK_MIN", "0"),
            ("SLURM_ARRAY_TASK_STEP", "2"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
        ];
        assert_eq!(
            resolve(Some("auto"), None, vars(&stepped)).unwrap(),
            Shard { index: 3, count: 4 }
        );
        assert!(resolve(Some("auto"), Some(5), vars(&slurm)).is_err());
        let k8s = [("JOB_COMPLETION_INDEX", "0")];
        assert_eq!(
            resolve(Some("auto"), Some(3), vars(&k8s)).unwrap(),
            Shard { index: 0, count: 3 }
        );
        let e = resolve(Some("auto"), None, vars(&k8s))
            .unwrap_err()
            .to_string();
        assert!(e.contains("--shard-count"), "{e}");
        let e = resolve(
            Some("auto"),
            Some(3),
            vars(&[("JOB_COMPLETION_INDEX", "3")]),
        );
        assert!(e.is_err());
        let e = resolve(Some("auto"), None, vars(&[]))
            .unwrap_err()
            .to_string();
        assert!(e.contains("SLURM_ARRAY_TASK_ID") && e.contains("JOB_COMPLETION_INDEX"));
    }
}
