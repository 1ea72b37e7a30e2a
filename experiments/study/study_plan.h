#pragma once
// Studies from the options of the commands (`bivo plan KIND` and the single-process
// commands themselves): paths made absolute (shards run in other folders and on other
// machines), everything that depends on the data decided here, once, so that the units are
// independent:
//   report: the sweep covers the sequences that have ground truth; the Pareto front of a
//   sequence is that of the middle pair of its processed window.
#include <string>
#include <vector>

#include "experiments/report_builder.h"
#include "experiments/study/study.h"

namespace bivo::experiments {

Study table_study(const MatrixOptions& options, const std::string& output);
Study sweep_study(const SweepOptions& options, const std::string& output);
// `pairs` as pareto_pairs() gives them.
Study pareto_pairs_study(const ParetoStudyOptions& options, const std::vector<int>& pairs, const std::string& output,
                         bool plots);
Study report_study(const ReportOptions& options, const std::string& output);
Study loso_study(const LosoOptions& options, const std::string& output);

// The options write_report() needs, back from a report study.
ReportOptions report_options(const Study& study);

// Absolute, normalized, without a trailing separator.
std::string absolute_path(const std::string& path);

}  // namespace bivo::experiments
