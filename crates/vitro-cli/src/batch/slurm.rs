//! `vitro batch EXPERIMENT --out DIR --slurm`: the `sbatch` script of a job array that makes
//! the experiment's shards (each task finds its shard in `SLURM_ARRAY_TASK_ID`), and the
//! `vitro merge` job that joins them once every task is done.

use std::path::Path;

/// How the job array is cut.
pub(crate) struct ArrayPlan<'a> {
    /// The experiment's name (the job's name).
    pub name: &'a str,
    /// The `vitro` binary the tasks run.
    pub vitro: &'a Path,
    /// The experiment file.
    pub experiment: &'a Path,
    /// Where the merged results go; the shards go to `DIR/shards/N`.
    pub out: &'a Path,
    /// Tasks in the array.
    pub tasks: u64,
    /// CPUs (and worker threads) per task.
    pub cpus: u32,
    /// Wall-time limit per task, as sbatch reads it (`MM`, `HH:MM:SS`, `D-HH:MM:SS`).
    pub time: &'a str,
    /// Runs in the whole experiment.
    pub runs: u64,
}

/// True if `t` reads as an sbatch time limit: digits, `:` and one optional `D-` prefix.
pub(crate) fn is_slurm_time(t: &str) -> bool {
    let (days, rest) = t.split_once('-').unwrap_or(("0", t));
    !rest.is_empty()
        && !days.is_empty()
        && days.chars().all(|c| c.is_ascii_digit())
        && rest.split(':').count() <= 3
        && rest
            .split(':')
            .all(|p| !p.is_empty() && p.chars().all(|c| c.is_ascii_digit()))
}

/// Single-quotes `s` for a POSIX shell.
fn quote(s: &str) -> String {
    format!("'{}'", s.replace('\'', r"'\''"))
}

/// The script: the array job, then the merge job that waits for it.
pub(crate) fn script(p: &ArrayPlan<'_>) -> String {
    let vitro = quote(&p.vitro.display().to_string());
    let exp = quote(&p.experiment.display().to_string());
    let out = p.out.display().to_string();
    let shards = quote(&format!("{out}/shards"));
    let name: String = (p.name.chars())
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    let per_task = p.runs.div_ceil(p.tasks.max(1));
    format!(
        r#"#!/bin/bash
# The experiment {exp}: {runs} runs in a Slurm job array of {tasks} tasks (about {per_task}
# runs each); `vitro batch` finds each task's shard in SLURM_ARRAY_TASK_ID, and the merge job
# joins the shards into {out_q} once every task is done. Submit with:  bash THIS_FILE
set -euo pipefail
mkdir -p {shards}
array=$(sbatch --parsable --job-name=vitro-{name} --array=0-{last} \
  --cpus-per-task={cpus} --ntasks=1 --time={time} --output={shards}/slurm-%A_%a.log \
  --wrap="{vitro} batch {exp} --out {shards_w}/\$SLURM_ARRAY_TASK_ID --jobs {cpus} --resume")
sbatch --parsable --job-name=vitro-{name}-merge --dependency=afterok:"$array" --ntasks=1 \
  --output={shards}/slurm-merge-%j.log \
  --wrap="{vitro} merge $(for i in $(seq 0 {last}); do printf '{shards_w}/%s ' "$i"; done)--out {out_w}"
echo "submitted job array $array ({tasks} tasks) and its merge"
"#,
        runs = p.runs,
        tasks = p.tasks,
        out_q = quote(&out),
        last = p.tasks.saturating_sub(1),
        cpus = p.cpus,
        time = p.time,
        shards_w = format!("{out}/shards"),
        out_w = out,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_limits() {
        for ok in ["30", "01:00:00", "2-00:00:00", "90:00"] {
            assert!(is_slurm_time(ok), "{ok}");
        }
        for bad in ["", "1h", "01:00:00:00", "a-01:00", "1:", "-1"] {
            assert!(!is_slurm_time(bad), "{bad}");
        }
    }

    #[test]
    fn the_script_names_the_array_and_the_merge() {
        let s = script(&ArrayPlan {
            name: "demo sweep",
            vitro: Path::new("/opt/vitro"),
            experiment: Path::new("experiments/demo_sweep.toml"),
            out: Path::new("results/sweep"),
            tasks: 4,
            cpus: 2,
            time: "00:30:00",
            runs: 30,
        });
        assert!(s.contains("--array=0-3"), "{s}");
        assert!(s.contains("--cpus-per-task=2"), "{s}");
        assert!(s.contains("--time=00:30:00"), "{s}");
        assert!(s.contains("--job-name=vitro-demo_sweep "), "{s}");
        assert!(s.contains("--dependency=afterok:\"$array\""), "{s}");
        assert!(s.contains("'/opt/vitro' merge"), "{s}");
        assert!(s.contains("about 8\n"), "{s}");
    }
}
