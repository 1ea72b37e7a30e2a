// Studies from command options (study_plan.h).
#include "experiments/study/study_plan.h"

#include <algorithm>
#include <filesystem>

#include "odometry/io/tum_dataset.h"
#include "solvers/error.h"

namespace bivo::experiments {
namespace {

std::vector<std::string> absolute_paths(const std::vector<std::string>& paths) {
  std::vector<std::string> out;
  for (const auto& p : paths) out.push_back(absolute_path(p));
  return out;
}

Study base_study(const std::string& kind, const odometry::TrackerOptions& tracker, const std::string& output) {
  if (output.empty()) throw Error("no output folder given");
  Study s;
  s.kind = kind;
  s.output = absolute_path(output);
  s.tracker = tracker;
  return s;
}

// What the report needs to know of a sequence before anything runs.
struct SequenceFacts {
  bool opened = false, groundtruth = false;
  int frames = 0;
};
SequenceFacts facts(const std::string& dir, const odometry::TrackerOptions& t) {
  SequenceFacts f;
  try {
    const odometry::io::TumSequence seq = odometry::io::open_tum_sequence(dir, odometry::sequence_options(t));
    f.opened = true;
    f.groundtruth = seq.groundtruth.has_value();
    f.frames = int(seq.frames.size());
  } catch (const Error&) {
    // The table's run of this sequence records why; it gets no sweep and no Pareto front.
  }
  return f;
}

}  // namespace

std::string absolute_path(const std::string& path) {
  std::filesystem::path p = std::filesystem::absolute(path).lexically_normal();
  if (p.filename().empty() && p.has_parent_path()) p = p.parent_path();
  return p.string();
}

Study table_study(const MatrixOptions& options, const std::string& output) {
  Study s = base_study("table", options.tracker, output);
  MatrixOptions t = options;
  t.sequences = absolute_paths(options.sequences);
  t.trajectory_dir.clear();
  s.table = t;
  check_study(s);
  return s;
}

Study sweep_study(const SweepOptions& options, const std::string& output) {
  Study s = base_study("sweep", options.tracker, output);
  SweepOptions o = options;
  o.sequences = absolute_paths(options.sequences);
  s.sweep = o;
  check_study(s);
  return s;
}

Study pareto_pairs_study(const ParetoStudyOptions& options, const std::vector<int>& pairs, const std::string& output,
                         bool plots) {
  Study s = base_study("pareto", options.tracker, output);
  s.plots = plots;
  ParetoPlan plan;
  plan.options = options;
  plan.options.sequence_dir.clear();
  plan.options.pair = 0;
  for (int k : pairs) plan.pairs.push_back({absolute_path(options.sequence_dir), k});
  s.pareto = plan;
  check_study(s);
  return s;
}

Study report_study(const ReportOptions& o, const std::string& output) {
  Study s = base_study("report", o.tracker, output);
  s.plots = o.plots;
  s.report = ReportText{o.title, o.preamble};
  MatrixOptions t;
  t.sequences = absolute_paths(o.sequences);
  t.methods = o.methods;
  t.first_frame = o.first_frame;
  t.max_frames = o.max_frames;
  t.rpe_delta = o.rpe_delta;
  s.table = t;
  std::vector<SequenceFacts> seq;
  for (const auto& dir : t.sequences) seq.push_back(facts(dir, o.tracker));
  if (!o.lambdas.empty() || !o.epsilons.empty()) {
    SweepOptions w;
    for (size_t k = 0; k < seq.size(); ++k) {
      if (seq[k].groundtruth) w.sequences.push_back(t.sequences[k]);
    }
    w.lambdas = o.lambdas;
    w.epsilons = o.epsilons;
    w.first_frame = o.first_frame;
    w.max_frames = o.sweep_max_frames;
    w.rpe_delta = o.rpe_delta;
    s.sweep = w;
  }
  if (o.pareto) {
    ParetoPlan plan;
    plan.options.level = o.pareto_level;
    plan.options.points = o.pareto_points;
    plan.options.methods.clear();
    for (const auto& m : o.methods) plan.options.methods.push_back(m.method);
    for (size_t k = 0; k < seq.size(); ++k) {
      // The middle pair of the window the table processes: pairs first .. end - 2.
      const int end = o.max_frames < 0 ? seq[k].frames : std::min(seq[k].frames, o.first_frame + o.max_frames);
      const int pairs = end - o.first_frame - 1;
      if (seq[k].opened && pairs >= 1) plan.pairs.push_back({t.sequences[k], o.first_frame + pairs / 2});
    }
    s.pareto = plan;
  }
  check_study(s);
  return s;
}

Study loso_study(const LosoOptions& options, const std::string& output) {
  Study s = base_study("loso", options.tracker, output);
  LosoOptions o = options;
  o.sequences = absolute_paths(options.sequences);
  s.loso = o;
  check_study(s);
  return s;
}

ReportOptions report_options(const Study& s) {
  if (s.kind != "report") throw Error("study of kind '" + s.kind + "' is not a report");
  ReportOptions o;
  o.title = s.report->title;
  o.preamble = s.report->preamble;
  o.sequences = s.table->sequences;
  o.methods = s.table->methods;
  o.tracker = s.tracker;
  o.first_frame = s.table->first_frame;
  o.max_frames = s.table->max_frames;
  o.rpe_delta = s.table->rpe_delta;
  if (s.sweep) {
    o.lambdas = s.sweep->lambdas;
    o.epsilons = s.sweep->epsilons;
    o.sweep_max_frames = s.sweep->max_frames;
  }
  o.pareto = s.pareto.has_value();
  if (s.pareto) {
    o.pareto_level = s.pareto->options.level;
    o.pareto_points = s.pareto->options.points;
  }
  o.plots = s.plots;
  return o;
}

}  // namespace bivo::experiments
