namespace bivo::problems {
const char* version() { return "0.1"; }
}  // namespace bivo::problems
