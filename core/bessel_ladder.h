#pragma once
// Bessel functions of the first kind on a ladder of orders ν0, ν0 + 1, …, ν0 + count − 1 at one argument, by
// Miller's backward recurrence J_{ν−1}(x) = (2ν/x) J_ν(x) − J_{ν+1}(x) (DLMF 10.6.1; stable downwards, where J is the
// minimal solution), started well above both the highest order and x and scaled by one direct evaluation at the
// rung where the recurrence's value is largest (never near a zero of J). The exact wedge series
// (core/wedge_series.h) needs J at orders m/n for m up to ~n(x + 40): for a sheet (n = 2) or a right-angled wedge
// (n = 3/2) those fall on two or three such ladders, so one direct call per ladder replaces one or two per term.
//
// Accuracy: relative 1e-12 of the ladder's largest value or better against std::cyl_bessel_j for x in (0, 200],
// ν0 in [0, 1), count ≤ 400 (tests/core/test_bessel_ladder.cpp). Pure function: thread-safe.
// Throws std::invalid_argument for x ≤ 0 or not finite, ν0 < 0, count < 0.
namespace rfidray {

void bessel_j_ladder(double nu0, double x, int count, double* out);

}  // namespace rfidray
