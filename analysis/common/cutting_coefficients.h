// Cutting-force coefficients of one tooth (000 eqs 2.1-2.2 with the edge terms of eqs 3.3-3.4):
//   F_t = Kt b w + Kte b,   F_r = Kr b w + Kre b.
// One type for the whole project: the dynamometer fit (Ktc, Kte, Krc, Kre of 000 sec. 3.2), the
// simulator's per-tooth values (milling::CuttingCoefficients) and the estimators' per-tooth
// Kt_p, Kr_p (estimate::ToothCoefficients).
#pragma once

#include <limits>

namespace chatterlab {

struct CuttingCoefficients {
  // Cutting (chip-area) terms, N/m^2: Ktc, Krc of 000 eqs 3.3-3.4 (eqs 2.1-2.2's Kt, Kr). No
  // default: a coefficient never measured or configured stays NaN.
  double Kt_N_m2 = std::numeric_limits<double>::quiet_NaN();  // tangential
  double Kr_N_m2 = std::numeric_limits<double>::quiet_NaN();  // radial
  // Edge (rubbing) terms, N/m: 0 unless a dynamometer fit measured them (the force model of
  // 000 eqs 2.1-2.2 and the identification of 000 sec. 5.1 have none), so {Kt, Kr} is a tooth
  // without edge force.
  double Kte_N_m = 0.0;  // tangential
  double Kre_N_m = 0.0;  // radial
};

// The cutting terms alone (000 sec. 5.1: the offset angle and the identification model the
// force by Kt, Kr of the dynamometer fit without its edge terms).
inline CuttingCoefficients without_edge_terms(const CuttingCoefficients& k) {
  return {k.Kt_N_m2, k.Kr_N_m2};
}

}  // namespace chatterlab
