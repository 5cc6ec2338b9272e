#include "raytrace/trace_options.h"

#include "core/error.h"

namespace rfidray {

const char* to_string(CandidateMode mode) {
  return mode == CandidateMode::kExhaustive ? "exhaustive" : "exact";
}

CandidateMode parse_candidate_mode(const std::string& name, const std::string& field) {
  if (name == "exhaustive") return CandidateMode::kExhaustive;
  if (name == "exact" || name == "fast") return CandidateMode::kExact;  // "fast": its former name
  throw field_error(field, "unknown candidate mode '" + clip(name) + "' (exact, exhaustive; fast = exact)");
}

}  // namespace rfidray
