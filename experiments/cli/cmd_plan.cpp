// `bivo plan KIND [the flags of bivo KIND] --study FILE [--shards N] [--slurm ...]
// [--parallel ...]`: writes the study that `bivo KIND` would run (experiments/study/study.h) for
// `bivo work` / `bivo merge`, and optionally the Slurm scripts or the GNU Parallel command
// line that run its shards (experiments/study/study_launch.h, docs/scaling.md).
#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>

#include "experiments/cli/commands.h"
#include "experiments/output_set.h"
#include "experiments/study/study_launch.h"
#include "experiments/study/study_plan.h"
#include "experiments/study/study_work.h"
#include "odometry/io/atomic_file.h"
#include "solvers/error.h"

namespace bivo::experiments::cli {
namespace {

namespace fs = std::filesystem;

// Slurm's default MaxArraySize is 1001 (indices 0..1000).
constexpr int kMaxArrayTasks = 1000;

struct PlanArgs {
  std::string study, results, bivo;
  int shards = 0;
  std::uint64_t seed = 1;
  bool slurm = false, parallel = false;
  LaunchOptions launch;
};

void add_plan_flags(CLI::App* cmd, PlanArgs& p) {
  cmd->add_option("--study", p.study, "the study file to write (JSON)")->required();
  cmd->add_option("--results", p.results, "folder of the unit result files (default: the study's name + .results)");
  cmd->add_option("--shards", p.shards, "shards for --slurm / --parallel (default: one per unit, at most 1000)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--seed", p.seed, "seed of the order in which units are dealt to shards")->capture_default_str();
  cmd->add_option("--bivo", p.bivo, "bivo executable the jobs run (default: this one)");
  cmd->add_flag("--slurm", p.slurm, "also write STUDY.sbatch (job array, one shard per task) and STUDY.submit.sh");
  cmd->add_option("--throttle", p.launch.throttle, "slurm: at most this many array tasks at once (%K)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--cpus-per-task", p.launch.threads, "slurm: CPUs of one shard (default: --threads if given, else 1)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--partition", p.launch.partition, "slurm: partition of the jobs");
  cmd->add_option("--time", p.launch.time_limit, "slurm: time limit of one shard, e.g. 2:00:00");
  cmd->add_option("--job-name", p.launch.job_name, "slurm: job name")->capture_default_str();
  cmd->add_option("--sbatch-option", p.launch.sbatch_args, "slurm: one more #SBATCH option, e.g. --mem=4G");
  cmd->add_flag("--parallel", p.parallel, "print the GNU Parallel command line that runs the shards, then the merge");
  cmd->add_option("--jobs", p.launch.jobs, "parallel: shards at once per host (default: one per CPU core)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--sshlogin", p.launch.sshlogins,
                  "parallel: run on these hosts ([N/]host, ':' = this machine); the paths must be the same there");
}

std::string stem_of(const std::string& study_path) {
  fs::path p(study_path);
  if (p.extension() == ".json") p.replace_extension();
  return p.string();
}

void plan(const Study& study, PlanArgs p, const std::string& config) {
  if (p.study.empty()) throw Error("give --study FILE");
  Study s = study;
  s.seed = p.seed;
  const std::string study_path = absolute_path(p.study);
  const std::string results = absolute_path(p.results.empty() ? default_results_dir(study_path) : p.results);
  const std::string stem = stem_of(study_path);
  // The study's files (and its results folder beside them by default) stay out of its inputs.
  std::vector<NamedPath> inputs = named_paths("a sequence of the study", study_sequences(s));
  inputs.push_back({"--config", config});
  check_output_files({{"--study", p.study},
                      {"the Slurm script", p.slurm ? stem + ".sbatch" : ""},
                      {"the Slurm script", p.slurm ? stem + ".submit.sh" : ""}},
                     inputs);
  write_study(study_path, s);
  const int units = int(study_units(s).size());
  int shards = p.shards > 0 ? p.shards : std::min(units, kMaxArrayTasks);
  std::cerr << "plan: " << study_path << ": " << s.kind << " study, " << units << " unit(s), hash " << study_hash(s)
            << "\n";
  LaunchOptions& o = p.launch;
  o.bivo = p.bivo.empty() ? fs::read_symlink("/proc/self/exe").string() : absolute_path(p.bivo);
  o.study_path = study_path;
  o.results_dir = results;
  o.shards = shards;
  if (p.slurm) {
    if (shards > kMaxArrayTasks) {
      std::cerr << "plan: warning: " << shards << " array tasks exceed Slurm's default MaxArraySize (1001)\n";
    }
    o.log_dir = stem + ".logs";
    const std::string array = stem + ".sbatch", submit = stem + ".submit.sh";
    const std::string array_text = slurm_array_script(o, submit), submit_text = slurm_submit_script(o, array);
    odometry::io::write_file_atomically(array, [&](std::ostream& out) { out << array_text; });
    odometry::io::write_file_atomically(submit, [&](std::ostream& out) { out << submit_text; });
    ::chmod(submit.c_str(), 0755);
    std::cerr << "plan: wrote " << array << " (array of " << shards << " shard(s)) and " << submit << "\n";
  }
  if (p.parallel) {
    std::cout << parallel_command(o) << std::flush;  // stdout: the command line alone
    return;
  }
  std::cout << "study " << study_path << " (" << units << " units)\n"
            << "run a shard:  " << shell_quote(o.bivo) << " work " << shell_quote(study_path) << " --shard I/" << shards
            << " --results " << shell_quote(results) << "   (I = 0.." << shards - 1 << ")\n"
            << "then merge:   " << shell_quote(o.bivo) << " merge " << shell_quote(study_path) << " "
            << shell_quote(results) << "\n";
  if (p.slurm) std::cout << "on Slurm:     bash " << shell_quote(stem + ".submit.sh") << "\n";
}

}  // namespace

void add_plan_command(CLI::App& app) {
  auto* cmd =
      app.add_subcommand("plan", "Write a study (units of table/sweep/pareto/report/loso) for bivo work and merge");
  cmd->require_subcommand(1);
  using AddFlags = StudyFactory (*)(CLI::App*);
  const std::vector<std::pair<const char*, AddFlags>> kinds = {{"table", add_table_flags},
                                                               {"sweep", add_sweep_flags},
                                                               {"pareto", add_pareto_flags},
                                                               {"report", add_report_flags},
                                                               {"loso", add_loso_flags}};
  for (const auto& [name, add_flags] : kinds) {
    auto* sub = cmd->add_subcommand(name, std::string("the study `bivo ") + name + "` runs, with the same flags");
    const StudyFactory make = add_flags(sub);
    auto p = std::make_shared<PlanArgs>();
    add_plan_flags(sub, *p);
    sub->callback([sub, make, p] {
      PlanArgs args = *p;
      // The command's own --threads (where it has one) is what a shard uses: ask Slurm for
      // as many CPUs per task, unless --cpus-per-task says otherwise.
      const CLI::Option* threads = sub->get_option_no_throw("--threads");
      if (threads && threads->count() > 0 && sub->get_option("--cpus-per-task")->count() == 0) {
        args.launch.threads = std::max(1, threads->as<int>());
      }
      const CLI::Option* config = sub->get_option_no_throw("--config");
      plan(make(), args, config && config->count() > 0 ? config->as<std::string>() : "");
    });
  }
}

}  // namespace bivo::experiments::cli
