#pragma once
// The command lines that hand a study's shards to a real scheduler (docs/scaling.md):
//   Slurm: a job-array script (one shard per array task) and a submit script that also
//          queues the merge as a job that starts only when every task succeeded
//          (--dependency=afterok; cancelled if one fails).
//   GNU Parallel: one command that runs the shards on local cores or over --sshlogin
//          hosts, then the merge when all succeeded.
// bivo does no scheduling of its own: retries, placement and throttling are the engines'.
#include <string>
#include <vector>

namespace bivo::experiments {

struct LaunchOptions {
  std::string bivo;         // absolute path of the bivo executable the jobs run
  std::string study_path;   // absolute
  std::string results_dir;  // absolute
  int shards = 1;
  int threads = 1;  // CPUs of one shard (Slurm --cpus-per-task)
  // Slurm
  int throttle = 0;  // at most this many array tasks at once (0: no limit)
  std::string job_name = "bivo";
  std::string partition, time_limit;     // empty: the cluster's defaults
  std::vector<std::string> sbatch_args;  // more #SBATCH options, e.g. "--mem=4G"
  std::string log_dir;                   // absolute; %x-%A_%a.out per task
  // GNU Parallel
  int jobs = 0;                        // shards at once per host (0: one per CPU core)
  std::vector<std::string> sshlogins;  // e.g. "8/node1", ":" (this machine)
};

// 'text' quoted for a POSIX shell (unquoted when it needs no quoting).
std::string shell_quote(const std::string& text);

// The array script (its comment names the submit script); throws bivo::Error on a path that
// #SBATCH lines cannot hold (spaces).
std::string slurm_array_script(const LaunchOptions& options, const std::string& submit_script_path);
// The submit script for the array script at array_script_path.
std::string slurm_submit_script(const LaunchOptions& options, const std::string& array_script_path);
// One shell command line: the shards under GNU Parallel, && the merge.
std::string parallel_command(const LaunchOptions& options);

}  // namespace bivo::experiments
