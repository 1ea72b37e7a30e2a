#include "experiments/method_matrix.h"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include <nlohmann/json.hpp>

#include "experiments/result_table.h"
#include "experiments/trajectory_evaluation.h"
#include "odometry/io/atomic_file.h"
#include "odometry/io/trajectory.h"
#include "solvers/error.h"

namespace bivo::experiments {

MethodSpec parse_method_spec(const std::string& text) {
  const auto colon = text.find(':');
  if (colon == std::string::npos) return {text, ""};
  return {text.substr(0, colon), text.substr(colon + 1)};
}

std::string label(const MethodSpec& spec) {
  return spec.backend.empty() ? spec.method : spec.method + " (" + spec.backend + ")";
}

std::string sequence_label(const std::string& dir) {
  auto name = std::filesystem::path(dir).lexically_normal().filename().string();
  if (name.empty()) name = std::filesystem::path(dir).lexically_normal().parent_path().filename().string();
  // Column headers: "freiburg1_rpy" rather than "rgbd_dataset_freiburg1_rpy".
  const std::string prefix = "rgbd_dataset_";
  if (name.rfind(prefix, 0) == 0 && name.size() > prefix.size()) name = name.substr(prefix.size());
  return name;
}

std::vector<std::string> sequence_labels(const std::vector<std::string>& dirs) {
  std::vector<std::string> labels;
  for (const auto& d : dirs) labels.push_back(sequence_label(d));
  const auto count = [](const std::vector<std::string>& v, const std::string& x) {
    return std::count(v.begin(), v.end(), x);
  };
  std::vector<std::string> out = labels;
  for (std::size_t k = 0; k < dirs.size(); ++k) {
    if (count(labels, labels[k]) < 2) continue;
    std::error_code ec;
    const std::string absolute = std::filesystem::weakly_canonical(std::filesystem::absolute(dirs[k]), ec).string();
    std::uint32_t h = 2166136261u;  // FNV-1a: stable across runs and machines, unlike std::hash
    for (const unsigned char c : (ec ? dirs[k] : absolute)) h = (h ^ c) * 16777619u;
    char hex[16];
    std::snprintf(hex, sizeof hex, "~%06x", unsigned(h & 0xFFFFFFu));
    out[k] = labels[k] + hex;
  }
  const std::vector<std::string> hashed = out;
  for (std::size_t k = 0; k < dirs.size(); ++k) {
    if (count(hashed, hashed[k]) > 1) out[k] = hashed[k] + "#" + std::to_string(k + 1);
  }
  return out;
}

void check_matrix_options(const MatrixOptions& options) {
  if (options.sequences.empty()) throw Error("no sequences given");
  if (options.methods.empty()) throw Error("no methods given");
  for (const auto& m : options.methods) {
    odometry::TrackerOptions t = with_frame_window(options.tracker, options.first_frame, options.max_frames);
    t.method = m.method;
    t.backend = m.backend;
    odometry::validate(t);
  }
}

MatrixCell run_matrix_cell(const MatrixOptions& options, int method, int sequence) {
  const MethodSpec& m = options.methods.at(method);
  MatrixCell cell;
  cell.sequence_dir = options.sequences.at(sequence);
  cell.sequence = sequence_labels(options.sequences).at(sequence);
  cell.spec = m;
  RunRequest req;
  req.sequence_dir = cell.sequence_dir;
  req.tracker = options.tracker;
  req.tracker.method = m.method;
  req.tracker.backend = m.backend;
  req.first_frame = options.first_frame;
  req.max_frames = options.max_frames;
  req.progress = options.progress;
  req.label = cell.sequence + " " + label(m);
  cell.backend = effective_backend(req.tracker);
  try {
    cell.run = run_sequence(req);
  } catch (const Error& e) {
    cell.note = std::string("run failed: ") + e.what();
    return cell;
  }
  if (!cell.run->groundtruth) {
    cell.note = "no groundtruth.txt";
  } else {
    try {
      std::string why;
      cell.rpe = rpe_if_long_enough(*cell.run->groundtruth, cell.run->trajectory, options.rpe_delta, why);
      cell.note = why;
    } catch (const Error& e) {
      cell.note = std::string("no RPE: ") + e.what();
    }
    try {
      cell.ate = odometry::io::absolute_trajectory_error(*cell.run->groundtruth, cell.run->trajectory);
    } catch (const Error& e) {
      cell.note += std::string(cell.note.empty() ? "" : "; ") + "no ATE: " + e.what();
    }
  }
  return cell;
}

MethodMatrix assemble_matrix(const MatrixOptions& options, std::vector<MatrixCell> cells) {
  if (cells.size() != options.methods.size() * options.sequences.size()) {
    throw Error("method matrix: " + std::to_string(cells.size()) + " cells for " +
                std::to_string(options.methods.size()) + " methods x " + std::to_string(options.sequences.size()) +
                " sequences");
  }
  MethodMatrix out;
  out.methods = options.methods;
  out.sequences = sequence_labels(options.sequences);
  out.cells = std::move(cells);
  out.rpe_delta = options.rpe_delta;
  return out;
}

void write_matrix_trajectories(const MethodMatrix& matrix, const std::string& dir) {
  for (const auto& cell : matrix.cells) {
    if (!cell.run) continue;
    odometry::io::create_output_directory(dir);
    odometry::io::write_tum_trajectory(dir + "/" + cell.sequence + "__" + cell.spec.method +
                                           (cell.spec.backend.empty() ? "" : "-" + cell.spec.backend) + ".txt",
                                       cell.run->trajectory);
  }
}

MethodMatrix run_matrix(const MatrixOptions& options) {
  check_matrix_options(options);
  std::vector<MatrixCell> cells;
  for (int m = 0; m < int(options.methods.size()); ++m) {
    for (int s = 0; s < int(options.sequences.size()); ++s) cells.push_back(run_matrix_cell(options, m, s));
  }
  MethodMatrix out = assemble_matrix(options, std::move(cells));
  if (!options.trajectory_dir.empty()) write_matrix_trajectories(out, options.trajectory_dir);
  return out;
}

namespace {

std::vector<std::string> row_labels(const MethodMatrix& m) {
  std::vector<std::string> rows;
  for (const auto& spec : m.methods) rows.push_back(label(spec));
  return rows;
}

template <class F>
ResultTable table_of(const MethodMatrix& m, const std::string& corner, F value, int precision) {
  ResultTable t(corner, row_labels(m), m.sequences);
  t.precision = precision;
  for (int r = 0; r < int(m.methods.size()); ++r) {
    for (int c = 0; c < int(m.sequences.size()); ++c) {
      if (const auto v = value(m.at(r, c))) {
        t.set(r, c, *v);
      } else if (is_too_short(m.at(r, c).note)) {
        t.set_text(r, c, "too short");
      }
    }
  }
  return t;
}

ResultTable rpe_trans_table(const MethodMatrix& m) {
  return table_of(
      m, "RPE trans [" + rpe_unit("m", m.rpe_delta) + "]",
      [](const MatrixCell& c) -> std::optional<double> {
        if (c.rpe) return c.rpe->trans_rmse;
        return std::nullopt;
      },
      6);
}
ResultTable rpe_rot_table(const MethodMatrix& m) {
  return table_of(
      m, "RPE rot [" + rpe_unit("deg", m.rpe_delta) + "]",
      [](const MatrixCell& c) -> std::optional<double> {
        if (c.rpe) return c.rpe->rot_rmse_deg;
        return std::nullopt;
      },
      4);
}
ResultTable ate_table(const MethodMatrix& m) {
  return table_of(
      m, "ATE [m]",
      [](const MatrixCell& c) -> std::optional<double> {
        if (c.ate) return c.ate->rmse;
        return std::nullopt;
      },
      6);
}
ResultTable runtime_table(const MethodMatrix& m) {
  ResultTable t = table_of(
      m, "ms per pair (median)",
      [](const MatrixCell& c) -> std::optional<double> {
        if (c.run) return c.run->median_ms;
        return std::nullopt;
      },
      2);
  return t;
}

// Median and mean over every pair of every sequence of one method (paper table 3).
struct MethodTiming {
  double median_ms = 0, mean_ms = 0;
  int pairs = 0;
};
MethodTiming method_timing(const MethodMatrix& m, int row) {
  std::vector<double> ms;
  for (int c = 0; c < int(m.sequences.size()); ++c) {
    const auto& cell = m.at(row, c);
    if (!cell.run) continue;
    for (const auto& p : cell.run->pairs) ms.push_back(1000.0 * p.seconds);
  }
  MethodTiming t;
  t.pairs = int(ms.size());
  if (ms.empty()) return t;
  double sum = 0;
  for (double v : ms) sum += v;
  t.mean_ms = sum / ms.size();
  std::sort(ms.begin(), ms.end());
  const size_t n = ms.size();
  t.median_ms = n % 2 ? ms[n / 2] : 0.5 * (ms[n / 2 - 1] + ms[n / 2]);
  return t;
}

std::string notes_markdown(const MethodMatrix& m) {
  std::ostringstream s;
  for (const auto& c : m.cells) {
    if (!c.note.empty()) s << "- " << c.sequence << " / " << label(c.spec) << ": " << c.note << "\n";
    if (c.run && c.run->failures > 0) {
      s << "- " << c.sequence << " / " << label(c.spec) << ": " << c.run->failures
        << " pair(s) with every pyramid level skipped (motion prior used)\n";
    }
  }
  return s.str();
}

}  // namespace

std::string matrix_markdown(const MethodMatrix& m) {
  std::ostringstream s;
  s << "Translational RPE RMSE over " << rpe_windows(m.rpe_delta) << " [" << rpe_unit("m", m.rpe_delta)
    << "] (paper tables 1/2; best per column in bold):\n\n"
    << rpe_trans_table(m).markdown() << "\nRotational RPE RMSE [" << rpe_unit("deg", m.rpe_delta) << "]:\n\n"
    << rpe_rot_table(m).markdown() << "\nATE RMSE after rigid alignment [m]:\n\n"
    << ate_table(m).markdown() << "\nTime per frame pair, median over pairs [ms] (loading excluded):\n\n"
    << runtime_table(m).markdown();
  s << "\nTime per frame pair over all sequences (paper table 3):\n\n| method | backend | pairs | median ms | mean ms "
       "|\n"
       "|---|---|---:|---:|---:|\n";
  for (int r = 0; r < int(m.methods.size()); ++r) {
    const MethodTiming t = method_timing(m, r);
    std::string backend = m.at(r, 0).backend;
    s << "| " << label(m.methods[r]) << " | " << backend << " | " << t.pairs << " | " << std::fixed
      << std::setprecision(2) << t.median_ms << " | " << t.mean_ms << " |\n";
  }
  const std::string notes = notes_markdown(m);
  if (!notes.empty()) s << "\nNotes:\n\n" << notes;
  return s.str();
}

std::string write_matrix(const MethodMatrix& m, const std::string& dir) {
  odometry::io::create_output_directory(dir);
  auto write = [&](const std::string& name, const std::string& text) {
    odometry::io::write_file_atomically(dir + "/" + name, [&](std::ostream& o) { o << text; });
  };
  const std::string md = matrix_markdown(m);
  write("rpe_trans.md", rpe_trans_table(m).markdown());
  write("rpe_trans.csv", rpe_trans_table(m).csv());
  write("rpe_rot.csv", rpe_rot_table(m).csv());
  write("ate.csv", ate_table(m).csv());
  write("runtime.md", runtime_table(m).markdown());
  write("runtime.csv", runtime_table(m).csv());
  write("tables.md", md);

  std::ostringstream bars;
  bars << "method,backend,median_ms,mean_ms,pairs\n";
  for (int r = 0; r < int(m.methods.size()); ++r) {
    const MethodTiming t = method_timing(m, r);
    if (t.pairs == 0) continue;
    bars << csv_field(label(m.methods[r])) << "," << m.at(r, 0).backend << "," << std::setprecision(8) << t.median_ms
         << "," << t.mean_ms << "," << t.pairs << "\n";
  }
  write("runtime_bars.csv", bars.str());

  std::ostringstream pairs;
  pairs << "sequence,method,pair,t,trans_err_m,rot_err_deg,ms,lambda,epsilon_per_weight,iterations\n";
  for (const auto& c : m.cells) {
    if (!c.run) continue;
    for (const auto& p : c.run->pairs) {
      if (!p.error) continue;
      pairs << csv_field(c.sequence) << "," << csv_field(label(c.spec)) << "," << p.index << ","
            << std::setprecision(17) << p.t_current << std::setprecision(8) << "," << p.error->translation_m << ","
            << p.error->rotation_deg << "," << 1000.0 * p.seconds << "," << p.lambda << "," << p.epsilon_per_weight
            << "," << p.iterations << "\n";
    }
  }
  write("pairs.csv", pairs.str());

  nlohmann::json j = nlohmann::json::array();
  for (const auto& c : m.cells) {
    nlohmann::json e = {{"sequence", c.sequence},
                        {"sequence_dir", c.sequence_dir},
                        {"method", c.spec.method},
                        {"backend", c.backend},
                        {"note", c.note}};
    if (c.run) {
      e["frames"] = c.run->trajectory.size();
      e["median_ms"] = c.run->median_ms;
      e["mean_ms"] = c.run->mean_ms;
      e["failures"] = c.run->failures;
      nlohmann::json phases;
      for (const auto& [name, sec] : c.run->profile.all()) phases[name] = 1000.0 * sec / c.run->pairs.size();
      e["ms_per_pair_by_phase"] = phases;
    }
    if (c.rpe) {
      e["rpe_trans_m_per_s"] = c.rpe->trans_rmse;
      e["rpe_rot_deg_per_s"] = c.rpe->rot_rmse_deg;
      e["rpe_trans_max"] = c.rpe->trans_max;
      e["rpe_windows"] = c.rpe->pairs.size();
    }
    if (c.ate) e["ate_m"] = c.ate->rmse;
    j.push_back(e);
  }
  write("results.json", j.dump(2) + "\n");
  return md;
}

}  // namespace bivo::experiments
