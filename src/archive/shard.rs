//! Sharding: one of N deterministic parts of an archive, for job arrays.
//!
//! Shard `I/N` (0 ≤ I < N) takes the eye-frames whose group number is I
//! modulo N (all tiles of an eye-frame stay together, so `--dedupe frame`
//! counts the same), or, without a manifest, the images whose position in
//! sorted path order is I modulo N. The index can come from the command line
//! or from the job array that started the process: Slurm (task
//! `MIN + I·STEP` of `MIN-MAX:STEP` is shard I, from `SLURM_ARRAY_TASK_ID`,
//! `_MIN`, `_MAX`, `_STEP` and `_COUNT`; what cannot be mapped is refused), Kubernetes Indexed Jobs (`JOB_COMPLETION_INDEX`
//! of `UFCSR_SHARD_COUNT`) and AWS Batch array jobs
//! (`AWS_BATCH_JOB_ARRAY_INDEX` of `UFCSR_SHARD_COUNT`). `ufcsr merge`
//! adds the shards' results back together.

use crate::error::{Error, Result};

pub use crate::format::result::Shard;

/// Most shards an archive may be split into.
pub(crate) const MAX_SHARDS: u32 = 1_000_000;

impl Shard {
    /// `I/N`, zero-based.
    pub fn new(index: u32, count: u32) -> Result<Shard> {
        if count == 0 || count > MAX_SHARDS || index >= count {
            return Err(Error::BadOptions(format!(
                "shard {index}/{count}: need 0 ≤ index < count ≤ {MAX_SHARDS} (indices start at 0)"
            )));
        }
        Ok(Shard { index, count })
    }

    /// True when eye-frame `group` (or image position) belongs to this shard.
    pub fn takes(&self, position: usize) -> bool {
        position % self.count as usize == self.index as usize
    }

    /// The shard a job array assigns through `lookup` (an environment
    /// reader), or `None` when no job array is visible.
    pub fn from_job_array(lookup: impl Fn(&str) -> Option<String>) -> Result<Option<Shard>> {
        let number = |name: &str| -> Result<Option<u32>> {
            match lookup(name) {
                None => Ok(None),
                Some(text) => text
                    .trim()
                    .parse()
                    .map(Some)
                    .map_err(|_| Error::BadOptions(format!("{name}={text:?} is not a whole number"))),
            }
        };
        if let Some(id) = number("SLURM_ARRAY_TASK_ID")? {
            let array = SlurmArray {
                id,
                count: number("SLURM_ARRAY_TASK_COUNT")?,
                min: number("SLURM_ARRAY_TASK_MIN")?,
                max: number("SLURM_ARRAY_TASK_MAX")?,
                step: number("SLURM_ARRAY_TASK_STEP")?,
            };
            return array.shard().map(Some);
        }
        for variable in ["JOB_COMPLETION_INDEX", "AWS_BATCH_JOB_ARRAY_INDEX"] {
            if let Some(index) = number(variable)? {
                let count = number("UFCSR_SHARD_COUNT")?.ok_or_else(|| {
                    Error::BadOptions(format!(
                        "{variable} is set: set UFCSR_SHARD_COUNT to the array size too"
                    ))
                })?;
                return Shard::new(index, count).map(Some);
            }
        }
        Ok(None)
    }
}

/// What Slurm says about a job array task.
struct SlurmArray {
    id: u32,
    count: Option<u32>,
    min: Option<u32>,
    max: Option<u32>,
    step: Option<u32>,
}

impl SlurmArray {
    /// The shard of this task: tasks `MIN, MIN+STEP, …, MAX` are shards
    /// `0, 1, …` of `(MAX−MIN)/STEP + 1`. Without MIN and MAX, tasks
    /// `0 … COUNT−1` (step 1). Anything else (a list such as `--array=1,3,8`,
    /// whose COUNT disagrees with MIN/MAX/STEP, an id off the step, no COUNT
    /// and no MIN/MAX) cannot be mapped to shards and is refused.
    fn shard(&self) -> Result<Shard> {
        let refuse = |why: String| {
            Error::BadOptions(format!("SLURM_ARRAY_TASK_ID={}: {why}; give --shard I/N instead", self.id))
        };
        let step = self.step.unwrap_or(1);
        if step == 0 {
            return Err(refuse("SLURM_ARRAY_TASK_STEP is 0".into()));
        }
        let (min, count) = match (self.min, self.max) {
            (Some(min), Some(max)) => {
                if max < min {
                    return Err(refuse(format!(
                        "SLURM_ARRAY_TASK_MAX {max} is below SLURM_ARRAY_TASK_MIN {min}"
                    )));
                }
                let count = (max - min) / step + 1;
                if self.count.is_some_and(|given| given != count) {
                    return Err(refuse(format!(
                        "SLURM_ARRAY_TASK_COUNT {} disagrees with {min}-{max}:{step} ({count} tasks): an array \
                         given as a list cannot be mapped to shards",
                        self.count.unwrap_or_default()
                    )));
                }
                (min, count)
            }
            (min, None) if step == 1 && self.count.is_some() => (min.unwrap_or(0), self.count.unwrap_or(1)),
            (_, None) if step == 1 => {
                return Err(refuse(
                    "SLURM_ARRAY_TASK_COUNT (or SLURM_ARRAY_TASK_MIN and _MAX) is not set, so the number of \
                     shards is unknown"
                        .into(),
                ));
            }
            _ => {
                return Err(refuse(
                    "SLURM_ARRAY_TASK_STEP needs SLURM_ARRAY_TASK_MIN and SLURM_ARRAY_TASK_MAX".into(),
                ));
            }
        };
        let offset = self
            .id
            .checked_sub(min)
            .ok_or_else(|| refuse(format!("the id is below SLURM_ARRAY_TASK_MIN {min}")))?;
        if offset % step != 0 {
            return Err(refuse(format!("the id is not MIN {min} plus a multiple of STEP {step}")));
        }
        Shard::new(offset / step, count).map_err(|e| refuse(e.to_string()))
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl std::str::FromStr for Shard {
    type Err = Error;

    fn from_str(text: &str) -> Result<Shard> {
        let bad = || Error::BadOptions(format!("--shard {text:?}: use I/N, e.g. 0/4 (indices start at 0)"));
        let (index, count) = text.split_once('/').ok_or_else(bad)?;
        Shard::new(index.trim().parse().map_err(|_| bad())?, count.trim().parse().map_err(|_| bad())?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_parse_and_come_from_job_arrays() {
        assert_eq!("1/4".parse::<Shard>().unwrap(), Shard { index: 1, count: 4 });
        for bad in ["4/4", "0/0", "1", "a/b", "-1/3"] {
            assert!(bad.parse::<Shard>().is_err(), "{bad}");
        }
        fn env<'a>(pairs: &'a [(&'static str, &'static str)]) -> impl Fn(&str) -> Option<String> + 'a {
            move |name: &str| pairs.iter().find(|(k, _)| *k == name).map(|(_, v)| v.to_string())
        }
        let slurm =
            [("SLURM_ARRAY_TASK_ID", "3"), ("SLURM_ARRAY_TASK_COUNT", "4"), ("SLURM_ARRAY_TASK_MIN", "1")];
        assert_eq!(Shard::from_job_array(env(&slurm)).unwrap(), Some(Shard { index: 2, count: 4 }));
        let stepped = [
            ("SLURM_ARRAY_TASK_ID", "4"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
            ("SLURM_ARRAY_TASK_MIN", "0"),
            ("SLURM_ARRAY_TASK_MAX", "6"),
            ("SLURM_ARRAY_TASK_STEP", "2"),
        ];
        assert_eq!(Shard::from_job_array(env(&stepped)).unwrap(), Some(Shard { index: 2, count: 4 }));
        let k8s = [("JOB_COMPLETION_INDEX", "0"), ("UFCSR_SHARD_COUNT", "2")];
        assert_eq!(Shard::from_job_array(env(&k8s)).unwrap(), Some(Shard { index: 0, count: 2 }));
        assert!(Shard::from_job_array(env(&[("AWS_BATCH_JOB_ARRAY_INDEX", "1")])).is_err());
        assert_eq!(Shard::from_job_array(env(&[])).unwrap(), None);
        let taken: Vec<usize> = (0..10).filter(|&p| Shard { index: 1, count: 3 }.takes(p)).collect();
        assert_eq!(taken, vec![1, 4, 7]);
    }
}
