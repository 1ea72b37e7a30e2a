// bivo_solvers needs one translation unit even before its backends exist.
namespace bivo::solvers {
const char* version() { return "0.1"; }
}  // namespace bivo::solvers
