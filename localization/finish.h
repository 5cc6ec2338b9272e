#pragma once
// Checks shared by the unwrapped-phase methods after they produced an estimate: residual, aperture angle,
// mirror ambiguity (judged on the unwrapped range cost, re-converged by Levenberg–Marquardt).
#include "localization/prepare.h"
#include "localization/range_cost.h"

namespace rfidray::loc {

// A gate that makes a result not ok but leaves its position worth reporting (uncertain): the caller goes on to
// the joint fit's radius and judgement, and reports this reason if they pass.
struct SoftGate {
  bool failed = false;
  FailReason reason = FailReason::kNone;
  std::string detail;
};

// The uncertainty gate: sets predicted_std_m and fails the result when it exceeds options.max_std_m.
// sigma_m: the per-read range noise estimated from the fit.
// With `soft`, the failure is written there and the result stays ok.
void gate_uncertainty(LocalizeResult& result, const PreparedTag& prep, const RangeCost& cost, double sigma_m,
                      const LocalizeOptions& options, SoftGate* soft = nullptr);

// check_mirror = false: the mirror test is left to the caller (the joint-model judgement, joint_fit.h).
// soft: where the gates that leave a position (cycle slips of the unwrapped phase, predicted σ) write their
// failure instead of failing the result; null: they fail it.
void finish_unwrapped(LocalizeResult& result, const PreparedTag& prep, const RangeCost& cost,
                      const LocalizeOptions& options, bool check_mirror = true, SoftGate* soft = nullptr);
// After the joint judgement: a result with a position takes the soft gate's failure (status uncertain).
void apply_soft_gate(LocalizeResult& result, const SoftGate& soft);

}  // namespace rfidray::loc
