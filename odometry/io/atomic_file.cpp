#include "odometry/io/atomic_file.h"

#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>

#include "solvers/error.h"

namespace bivo::odometry::io {

std::string temporary_path_for(const std::string& path) {
  std::random_device rd;
  std::ostringstream s;
  s << path << ".tmp" << std::hex << rd();
  return s.str();
}

void commit_temporary(const std::string& temporary, const std::string& path) {
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    std::remove(temporary.c_str());
    throw Error("cannot write '" + path + "': rename from temporary file failed");
  }
}

void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  const std::string tmp = temporary_path_for(path);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw Error("cannot write '" + path + "': directory missing or not writable");
    try {
      write(out);
    } catch (...) {
      out.close();
      std::remove(tmp.c_str());
      throw;
    }
    out.flush();
    if (!out) {
      out.close();
      std::remove(tmp.c_str());
      throw Error("cannot write '" + path + "': write failed (disk full?)");
    }
  }
  commit_temporary(tmp, path);
}

}  // namespace bivo::odometry::io
