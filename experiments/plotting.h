#pragma once
// Runs the matplotlib scripts of experiments/plots/ with /usr/bin/python3 (the python3 on
// PATH may lack numpy): plot(script, {inputs..., output.png}).
#include <string>
#include <vector>

namespace bivo::experiments {

// Folder of the scripts: $BIVO_PLOTS_DIR when set, else the installed one beside the
// executable (bin/../share/bivo/plots), else the source tree's (compile time); throws
// bivo::Error naming the places looked at when none has them.
std::string plots_dir();

// Runs `python3 <plots_dir>/<script> args...`; throws bivo::Error with the script's exit
// status and stderr tail when it fails or the interpreter is missing.
void plot(const std::string& script, const std::vector<std::string>& args);

}  // namespace bivo::experiments
