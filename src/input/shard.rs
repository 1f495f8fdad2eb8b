//! Sharding: one of N deterministic parts of an archive, for job arrays.
//!
//! Shard `I/N` (0 ≤ I < N) takes the eye-frames whose group number is I
//! modulo N (all tiles of an eye-frame stay together, so `--dedupe frame`
//! counts the same), or, without a manifest, the images whose position in
//! sorted path order is I modulo N. The index can come from the command line
//! or from the job array that started the process: Slurm
//! (`SLURM_ARRAY_TASK_ID` − `SLURM_ARRAY_TASK_MIN` of
//! `SLURM_ARRAY_TASK_COUNT`), Kubernetes Indexed Jobs (`JOB_COMPLETION_INDEX`
//! of `UFCSR_SHARD_COUNT`) and AWS Batch array jobs
//! (`AWS_BATCH_JOB_ARRAY_INDEX` of `UFCSR_SHARD_COUNT`). `ufcsr-analyze merge`
//! adds the shards' results back together.

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};

/// Shard `index` of `count`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    pub index: u32,
    pub count: u32,
}

/// Most shards an archive may be split into.
pub const MAX_SHARDS: u32 = 1_000_000;

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
        if let (Some(id), Some(count)) = (number("SLURM_ARRAY_TASK_ID")?, number("SLURM_ARRAY_TASK_COUNT")?) {
            let min = number("SLURM_ARRAY_TASK_MIN")?.unwrap_or(0);
            let index = id.checked_sub(min).ok_or_else(|| {
                Error::BadOptions(format!("SLURM_ARRAY_TASK_ID {id} is below SLURM_ARRAY_TASK_MIN {min}"))
            })?;
            return Shard::new(index, count).map(Some);
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
        let k8s = [("JOB_COMPLETION_INDEX", "0"), ("UFCSR_SHARD_COUNT", "2")];
        assert_eq!(Shard::from_job_array(env(&k8s)).unwrap(), Some(Shard { index: 0, count: 2 }));
        assert!(Shard::from_job_array(env(&[("AWS_BATCH_JOB_ARRAY_INDEX", "1")])).is_err());
        assert_eq!(Shard::from_job_array(env(&[])).unwrap(), None);
        let taken: Vec<usize> = (0..10).filter(|&p| Shard { index: 1, count: 3 }.takes(p)).collect();
        assert_eq!(taken, vec![1, 4, 7]);
    }
}
