// The tracker options' flags, made from their table (tracker_flags.h).
#include "experiments/cli/tracker_flags.h"

#include "experiments/tracker_config.h"
#include "odometry/odometry_methods.h"
#include "solvers/error.h"

namespace bivo::experiments::cli {

namespace {

using odometry::TrackerOptions;

// Options that choose or tune a method: only on commands that run one method.
bool is_method_option(const TrackerOption& o) {
  return o.key == "method" || o.key == "backend" || o.key.rfind("policy.", 0) == 0;
}

const char* type_name(OptionType type) {
  switch (type) {
    case OptionType::kNumber:
    case OptionType::kOptionalNumber:
      return "FLOAT";
    case OptionType::kInteger:
      return "INT";
    case OptionType::kBoolean:
      return "BOOL";
    case OptionType::kIntrinsics:
      return "\"FX FY CX CY\"";
    case OptionType::kDistortion:
      return "\"K1 K2 P1 P2 K3\"";
    default:
      return "TEXT";
  }
}

std::string help_of(const TrackerOption& o) {
  std::string help = o.method.empty() ? o.help : "method " + o.method + ": " + o.help;
  if (o.key == "method") return help + " (required unless --config names one)";
  const nlohmann::json d = o.get(TrackerOptions{});
  const std::string shown = d.is_null()           ? "none"
                            : d.is_string()       ? (d.get<std::string>().empty() ? "\"\"" : d.get<std::string>())
                            : d.is_number_float() ? format_option_number(d.get<double>())
                                                  : d.dump();
  switch (o.type) {
    case OptionType::kNumber:
    case OptionType::kInteger:
    case OptionType::kOptionalNumber:
    case OptionType::kBoolean:
      help += " " + o.range_text();
      break;
    default:
      break;
  }
  return help + " (default: " + shown + ")";
}

}  // namespace

TrackerFlags::TrackerFlags(CLI::App* cmd, bool with_method, bool with_backend) : with_method_(with_method) {
  cmd->add_option("--config", *config_,
                  "tracker configuration (JSON, as written next to every result); flags given as well override it")
      ->check(CLI::ExistingFile);
  for (const TrackerOption& o : tracker_option_table()) {
    if (o.flag.empty()) continue;  // set by the command's own flags (--max-frames) or by the method
    const bool wanted = !is_method_option(o) || with_method || (with_backend && o.key == "backend");
    if (!wanted) continue;
    auto text = std::make_shared<std::string>();
    CLI::Option* cli = cmd->add_option(o.flag, *text, help_of(o))->type_name(type_name(o.type));
    flags_.push_back({&o, cli, text});
  }
}

TrackerOptions TrackerFlags::options() const {
  TrackerOptions o = config_->empty() ? TrackerOptions{} : read_tracker_config(*config_);
  bool method_given = false;
  for (const auto& f : flags_) {
    if (f.cli->count() == 0) continue;
    method_given = method_given || f.option->key == "method";
    try {
      apply_tracker_option(*f.option, tracker_flag_value(*f.option, *f.text), o);
    } catch (const Error& e) {
      throw Error(f.option->flag + ": " + e.what());
    }
  }
  if (with_method_) {
    if (config_->empty() && !method_given) throw Error("give --method (or a --config file that names one)");
    // A file without "method" would run the default method without anybody having chosen it.
    if (!method_given && !tracker_config_names_method(*config_)) {
      throw Error(*config_ + ": names no method; give --method or a \"method\" key");
    }
    const odometry::Method method = odometry::parse_method(o.method);
    for (const auto& f : flags_) {
      if (f.cli->count() > 0 && !f.option->method.empty() && method != odometry::parse_method(f.option->method)) {
        throw Error(f.option->flag + " applies to method '" + f.option->method + "' only (method is '" + o.method +
                    "')");
      }
    }
  }
  odometry::validate(o);
  return o;
}

}  // namespace bivo::experiments::cli
