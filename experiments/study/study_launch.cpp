// Slurm scripts and the GNU Parallel command line (study_launch.h).
#include "experiments/study/study_launch.h"

#include <sstream>

#include "solvers/error.h"

namespace bivo::experiments {
namespace {

void check_sbatch_value(const std::string& what, const std::string& value) {
  if (value.find_first_of(" \t\n\"'") != std::string::npos) {
    throw Error("slurm: " + what + " '" + value + "' contains a space or quote, which #SBATCH lines cannot hold");
  }
}

std::string work_command(const LaunchOptions& o, const std::string& shard) {
  return shell_quote(o.bivo) + " work " + shell_quote(o.study_path) + " --shard " + shard + " --results " +
         shell_quote(o.results_dir);
}

std::string merge_command(const LaunchOptions& o) {
  return shell_quote(o.bivo) + " merge " + shell_quote(o.study_path) + " " + shell_quote(o.results_dir);
}

}  // namespace

std::string shell_quote(const std::string& text) {
  if (!text.empty() && text.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789"
                                              "_-./=:,+@%") == std::string::npos) {
    return text;
  }
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string slurm_array_script(const LaunchOptions& o, const std::string& submit_script_path) {
  if (o.shards < 1) throw Error("slurm: at least one shard");
  check_sbatch_value("log folder", o.log_dir);
  check_sbatch_value("job name", o.job_name);
  std::ostringstream s;
  s << "#!/bin/bash\n"
    << "# One shard of the study per array task (bivo work). Submit with its merge job:\n"
    << "#   bash " << shell_quote(submit_script_path) << "\n"
    << "#SBATCH --job-name=" << o.job_name << "\n"
    << "#SBATCH --array=0-" << o.shards - 1;
  if (o.throttle > 0) s << "%" << o.throttle;
  s << "\n#SBATCH --ntasks=1\n#SBATCH --cpus-per-task=" << o.threads << "\n"
    << "#SBATCH --output=" << o.log_dir << "/%x-%A_%a.out\n";
  if (!o.partition.empty()) s << "#SBATCH --partition=" << o.partition << "\n";
  if (!o.time_limit.empty()) s << "#SBATCH --time=" << o.time_limit << "\n";
  for (const auto& a : o.sbatch_args) {
    check_sbatch_value("sbatch option", a);
    s << "#SBATCH " << a << "\n";
  }
  s << "set -euo pipefail\n"
    << "exec " << work_command(o, "\"${SLURM_ARRAY_TASK_ID}/" + std::to_string(o.shards) + "\"") << "\n";
  return s.str();
}

std::string slurm_submit_script(const LaunchOptions& o, const std::string& array_script_path) {
  std::ostringstream s;
  s << "#!/bin/bash\n"
    << "# Submits the study's job array (" << o.shards << " shard(s)) and its merge, which starts when every\n"
    << "# array task succeeded (afterok) and is cancelled when one failed; re-submitting resumes.\n"
    << "set -euo pipefail\n"
    << "mkdir -p " << shell_quote(o.log_dir) << "\n"
    << "array=$(sbatch --parsable " << shell_quote(array_script_path) << ")\n"
    << "array=${array%%;*}\n"
    << "merge=$(sbatch --parsable --job-name=" << o.job_name << "-merge --dependency=afterok:${array} "
    << "--kill-on-invalid-dep=yes --ntasks=1 --output=" << shell_quote(o.log_dir + "/%x-%j.out");
  if (!o.partition.empty()) s << " --partition=" << shell_quote(o.partition);
  if (!o.time_limit.empty()) s << " --time=" << shell_quote(o.time_limit);
  s << " --wrap=" << shell_quote("exec " + merge_command(o)) << ")\n"
    << "echo \"bivo: array job ${array} (" << o.shards << " shards), merge job ${merge}\"\n";
  return s.str();
}

std::string parallel_command(const LaunchOptions& o) {
  if (o.shards < 1) throw Error("parallel: at least one shard");
  std::ostringstream s;
  // --quote: the paths reach the (remote) shell as single words; --halt never: every shard
  // is tried, the exit status counts the failures, and the merge runs only when it is 0.
  s << "parallel --quote --halt never";
  if (o.jobs > 0) s << " --jobs " << o.jobs;
  for (const auto& h : o.sshlogins) s << " --sshlogin " << shell_quote(h);
  s << " " << work_command(o, "{}/" + std::to_string(o.shards)) << " ::: $(seq 0 " << o.shards - 1 << ") && "
    << merge_command(o) << "\n";
  return s.str();
}

}  // namespace bivo::experiments
