// How far ray optics is from the exact field near a perfectly conducting edge (docs/fullwave.md, "The exact
// wedge"): the canonical problem of core/wedge_series.h (a plane wave from φ' on a sheet's edge, n = 2, and on a
// right-angled wedge, n = 1.5) at kρ = 0.25 … 16, observers every 0.5° round the exterior; the error of geometrical
// optics (single-bounce and below), of GO + UTD (full-selective, full without the near field) and, across the edge,
// of the ray fields' E. Median and max over angles and the source angles below, as a CSV on stdout.
//   bench/wedge_canonical_error > bench/results/fullwave/wedge_canonical_error.csv
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "core/units.h"
#include "core/wedge_series.h"

using namespace rfidray;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace

int main() {
  const double k = wavenumber_rad_m(866e6);
  std::printf("n,krho,go_soft_median,go_soft_max,utd_soft_median,utd_soft_max,go_hard_e_median,go_hard_e_max,"
              "utd_hard_e_median,utd_hard_e_max\n");
  for (double n : {2.0, 1.5})
    for (double krho : {0.25, 0.5, 0.73, 1.0, 1.45, 2.0, 2.9, 4.0, 5.8, 8.0, 12.0, 16.0}) {
      std::vector<double> go_soft, utd_soft, go_hard, utd_hard;
      for (double pp_deg : {20.0, 60.0, 100.0, 140.0, 200.0, 250.0}) {
        if (pp_deg >= n * 180.0) continue;
        const double pp = pp_deg * kPi / 180.0, rho = krho / k;
        for (double phi_deg = 0.25; phi_deg < n * 180.0; phi_deg += 0.5) {
          const double phi = phi_deg * kPi / 180.0;
          const WedgeField e = wedge_plane_wave_exact(n, rho, phi, pp, k);
          const WedgeField g = wedge_plane_wave_geometrical_optics(n, rho, phi, pp, k);
          const WedgeField u = wedge_plane_wave_utd(n, rho, phi, pp, k);
          const auto hard = [&](const WedgeField& r) {
            return std::hypot(std::abs(r.hard_e_rho - e.hard_e_rho), std::abs(r.hard_e_phi - e.hard_e_phi));
          };
          go_soft.push_back(std::abs(g.soft - e.soft));
          utd_soft.push_back(std::abs(u.soft - e.soft));
          go_hard.push_back(hard(g));
          utd_hard.push_back(hard(u));
        }
      }
      const auto max = [](const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); };
      std::printf("%g,%g,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f\n", n, krho, median(go_soft), max(go_soft),
                  median(utd_soft), max(utd_soft), median(go_hard), max(go_hard), median(utd_hard), max(utd_hard));
    }
  return 0;
}
