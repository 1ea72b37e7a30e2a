// The CBF reader (cbf_file.h): a line-numbered pass over the keyword blocks, then the
// conversion to the IPM's form as sparse row selections of [A; I] (one per cone kind).
#include "experiments/conic_files/cbf_file.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "solvers/error.h"

namespace bivo::experiments {

namespace {

using solvers::conic::ConicProblem;
using solvers::conic::SparseMatrix;
using Triplets = std::vector<Eigen::Triplet<double>>;

enum class Cone { kFree, kNonnegative, kNonpositive, kZero, kQuadratic, kRotated };

struct ConeBlock {
  Cone kind;
  int dim;
};

// Lines with their numbers; comments (#...) and blank lines are skipped. A line is blank when
// it has no token by the same rule that splits tokens (any isspace character: a line of form
// feeds is blank, not a line with zero tokens -- fuzz_cbf, line_of_form_feeds.cbf).
class LineReader {
 public:
  LineReader(std::istream& in, std::string name) : in_(in), name_(std::move(name)) {}
  bool next(std::vector<std::string>& tokens) {
    std::string line;
    while (std::getline(in_, line)) {
      ++number_;
      tokens.clear();
      std::istringstream ss(line);
      for (std::string t; ss >> t;) tokens.push_back(t);
      if (!tokens.empty() && tokens[0][0] != '#') return true;
    }
    return false;
  }
  // The next data line of `block`, with exactly `count` tokens.
  std::vector<std::string> data(const std::string& block, std::size_t count) {
    std::vector<std::string> t;
    if (!next(t)) fail(block + ": the file ends inside the block");
    if (t.size() != count) {
      fail(block + ": expected " + std::to_string(count) + " entries on this line, found " + std::to_string(t.size()));
    }
    return t;
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw Error(name_ + ":" + std::to_string(number_) + ": " + what);
  }
  long integer(const std::string& s, const std::string& what, long lo, long hi) const {
    errno = 0;
    char* end = nullptr;
    const long v = std::strtol(s.c_str(), &end, 10);
    if (s.empty() || *end != '\0' || errno == ERANGE) fail(what + ": '" + s + "' is not an integer");
    if (v < lo || v > hi) {
      fail(what + " " + s + " is out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    }
    return v;
  }
  double real(const std::string& s, const std::string& what) const {
    errno = 0;
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (s.empty() || *end != '\0' || errno == ERANGE || !std::isfinite(v)) {
      fail(what + ": '" + s + "' is not a finite number");
    }
    return v;
  }

 private:
  std::istream& in_;
  std::string name_;
  int number_ = 0;
};

constexpr long kMaxDim = 1L << 30;

Cone cone_kind(const std::string& s, const LineReader& r) {
  if (s == "F") return Cone::kFree;
  if (s == "L+") return Cone::kNonnegative;
  if (s == "L-") return Cone::kNonpositive;
  if (s == "L=") return Cone::kZero;
  if (s == "Q") return Cone::kQuadratic;
  if (s == "QR") return Cone::kRotated;
  r.fail("cone '" + s + "' is not supported (bivo's IPM takes F, L+, L-, L=, Q, QR)");
}

// "n k" then k lines "CONE dim" whose dims sum to n.
std::vector<ConeBlock> read_cones(LineReader& r, const std::string& block, int& total) {
  const auto head = r.data(block, 2);
  total = static_cast<int>(r.integer(head[0], block + " size", 0, kMaxDim));
  const long k = r.integer(head[1], block + " cone count", 0, total);
  std::vector<ConeBlock> cones;
  long sum = 0;
  for (long i = 0; i < k; ++i) {
    const auto t = r.data(block, 2);
    const Cone kind = cone_kind(t[0], r);
    const long min_dim = kind == Cone::kRotated ? 2 : 1;
    const int dim = static_cast<int>(r.integer(t[1], block + " cone " + t[0] + " dimension", min_dim, kMaxDim));
    sum += dim;
    if (sum > total) r.fail(block + ": cone dimensions exceed the declared size " + std::to_string(total));
    cones.push_back({kind, dim});
  }
  if (sum != total) {
    r.fail(block + ": cone dimensions sum to " + std::to_string(sum) + ", the header declares " +
           std::to_string(total));
  }
  return cones;
}

struct ParsedCbf {
  bool maximize = false;
  int n = -1, m = 0;
  std::vector<ConeBlock> var_cones, con_cones;
  Triplets c, a;
  std::vector<Eigen::Triplet<double>> b;
  double c0 = 0.0;
};

// n + m in 64 bits (each <= 2^30) against the limit, before anything of that size exists.
void check_size(const LineReader& r, const ParsedCbf& p) {
  const std::int64_t size = std::int64_t{p.n} + p.m, limit = std::min<std::int64_t>(max_cbf_size(), kMaxDim);
  if (size > limit) {
    r.fail(std::to_string(p.n) + " variables + " + std::to_string(p.m) + " constraints exceed the limit of " +
           std::to_string(limit) + " (raise with --max-conic-size)");
  }
}

ParsedCbf parse_blocks(LineReader& r) {
  ParsedCbf p;
  bool have_version = false, have_con = false;
  std::vector<std::string> t;
  while (r.next(t)) {
    const std::string key = t[0];
    if (t.size() != 1) r.fail("expected a keyword alone on its line, found '" + key + " ...'");
    if (!have_version && key != "VER") r.fail("the file must start with VER, found '" + key + "'");
    if (key == "VER") {
      if (have_version) r.fail("VER given twice");
      r.integer(r.data(key, 1)[0], "VER version", 1, 4);
      have_version = true;
    } else if (key == "OBJSENSE") {
      const std::string s = r.data(key, 1)[0];
      if (s != "MIN" && s != "MAX") r.fail("OBJSENSE must be MIN or MAX, found '" + s + "'");
      p.maximize = s == "MAX";
    } else if (key == "VAR") {
      if (p.n >= 0) r.fail("VAR given twice");
      p.var_cones = read_cones(r, key, p.n);
      check_size(r, p);
    } else if (key == "CON") {
      if (have_con) r.fail("CON given twice");
      if (p.n < 0) r.fail("CON must come after VAR");
      p.con_cones = read_cones(r, key, p.m);
      have_con = true;
      check_size(r, p);
    } else if (key == "OBJACOORD" || key == "ACOORD" || key == "BCOORD") {
      if (p.n < 0) r.fail(key + " must come after VAR");
      if (key != "OBJACOORD" && !have_con) r.fail(key + " must come after CON");
      const long nnz = r.integer(r.data(key, 1)[0], key + " entry count", 0, kMaxDim);
      const std::size_t width = key == "ACOORD" ? 3 : 2;
      for (long e = 0; e < nnz; ++e) {
        const auto d = r.data(key, width);
        const double v = r.real(d[width - 1], key + " value");
        if (key == "OBJACOORD") {
          p.c.emplace_back(static_cast<int>(r.integer(d[0], key + " variable index", 0, p.n - 1)), 0, v);
        } else if (key == "BCOORD") {
          p.b.emplace_back(static_cast<int>(r.integer(d[0], key + " constraint index", 0, p.m - 1)), 0, v);
        } else {
          const int i = static_cast<int>(r.integer(d[0], key + " constraint index", 0, p.m - 1));
          p.a.emplace_back(i, static_cast<int>(r.integer(d[1], key + " variable index", 0, p.n - 1)), v);
        }
      }
    } else if (key == "OBJBCOORD") {
      p.c0 = r.real(r.data(key, 1)[0], key);
    } else if (key == "INT") {
      r.fail("INT: integer variables are not supported (bivo's IPM solves continuous problems)");
    } else if (key == "PSDVAR" || key == "PSDCON" || key == "OBJFCOORD" || key == "FCOORD" || key == "HCOORD" ||
               key == "DCOORD") {
      r.fail(key + ": semidefinite variables/constraints are not supported");
    } else if (key == "POWCONES" || key == "POW*CONES") {
      r.fail(key + ": power cones are not supported");
    } else if (key == "CHANGE") {
      r.fail("CHANGE: instance sequences are not supported");
    } else {
      r.fail("unknown keyword '" + key + "'");
    }
  }
  if (!have_version) r.fail("empty file: no VER");
  if (p.n < 0) r.fail("no VAR block");
  return p;
}

// Rows of the IPM form as combinations of the source rows [A; I] (constraint i, variable m + j).
struct RowSelection {
  Triplets eq, cone;
  int eq_rows = 0, orthant_rows = 0;
  std::vector<int> soc;
  Triplets soc_rows;
  int soc_row_count = 0;
  void add_block(const ConeBlock& block, int src) {
    const double r = std::sqrt(0.5);
    for (int k = 0; k < block.dim; ++k) {
      switch (block.kind) {
        case Cone::kFree:
          break;
        case Cone::kZero:
          eq.emplace_back(eq_rows++, src + k, 1.0);
          break;
        case Cone::kNonnegative:
          cone.emplace_back(orthant_rows++, src + k, 1.0);
          break;
        case Cone::kNonpositive:
          cone.emplace_back(orthant_rows++, src + k, -1.0);
          break;
        case Cone::kQuadratic:
          soc_rows.emplace_back(soc_row_count + k, src + k, 1.0);
          break;
        case Cone::kRotated:
          if (k == 0) {  // (u + v)/sqrt 2, (u - v)/sqrt 2
            soc_rows.emplace_back(soc_row_count, src, r);
            soc_rows.emplace_back(soc_row_count, src + 1, r);
            soc_rows.emplace_back(soc_row_count + 1, src, r);
            soc_rows.emplace_back(soc_row_count + 1, src + 1, -r);
          } else if (k >= 2) {
            soc_rows.emplace_back(soc_row_count + k, src + k, 1.0);
          }
          break;
      }
    }
    if (block.kind == Cone::kQuadratic || block.kind == Cone::kRotated) {
      soc.push_back(block.dim);
      soc_row_count += block.dim;
    }
  }
};

CbfProblem convert(const ParsedCbf& p) {
  const int n = p.n, m = p.m, src_rows = m + n;
  Triplets s = p.a;
  for (int j = 0; j < n; ++j) s.emplace_back(m + j, j, 1.0);
  SparseMatrix S(src_rows, n);
  S.setFromTriplets(s.begin(), s.end());
  Eigen::VectorXd bs = Eigen::VectorXd::Zero(src_rows), c = Eigen::VectorXd::Zero(n);
  for (const auto& t : p.b) bs[t.row()] += t.value();
  for (const auto& t : p.c) c[t.row()] += t.value();

  RowSelection sel;
  int src = 0;
  for (const auto& b : p.con_cones) {
    sel.add_block(b, src);
    src += b.dim;
  }
  for (const auto& b : p.var_cones) {
    sel.add_block(b, src);
    src += b.dim;
  }
  // Second-order rows follow the orthant rows.
  for (const auto& t : sel.soc_rows) sel.cone.emplace_back(sel.orthant_rows + t.row(), t.col(), t.value());

  SparseMatrix Peq(sel.eq_rows, src_rows), Pcone(sel.orthant_rows + sel.soc_row_count, src_rows);
  Peq.setFromTriplets(sel.eq.begin(), sel.eq.end());
  Pcone.setFromTriplets(sel.cone.begin(), sel.cone.end());

  CbfProblem out;
  out.maximize = p.maximize;
  out.objective_constant = p.c0;
  ConicProblem& q = out.problem;
  q.c = p.maximize ? Eigen::VectorXd(-c) : c;
  // s = P (S x + bs) in K  <=>  G x + s = h with G = -P S, h = P bs; equalities P S x = -P bs.
  q.A = Peq * S;
  q.b = -(Peq * bs);
  q.G = Pcone * S;
  q.G *= -1.0;
  q.h = Pcone * bs;
  q.A.prune(0.0);
  q.G.prune(0.0);
  q.A.makeCompressed();
  q.G.makeCompressed();
  q.cones.nonnegative = sel.orthant_rows;
  q.cones.soc = sel.soc;
  return out;
}

}  // namespace

std::int64_t& max_cbf_size() {
  static std::int64_t limit = std::int64_t{1} << 24;
  return limit;
}

CbfProblem parse_cbf(std::istream& in, const std::string& name) {
  LineReader reader(in, name);
  CbfProblem out = convert(parse_blocks(reader));
  try {
    solvers::conic::validate(out.problem);
  } catch (const Error& e) {
    throw Error(name + ": " + e.what());
  }
  return out;
}

CbfProblem read_cbf(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error("cannot open CBF file '" + path + "'");
  return parse_cbf(in, path);
}

bool is_cbf_path(const std::string& path) {
  if (path.size() < 4) return false;
  std::string ext = path.substr(path.size() - 4);
  for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return ext == ".cbf";
}

}  // namespace bivo::experiments
