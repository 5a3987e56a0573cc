// fields() of the analysis structs that kinds' results hold (app/core/archive.h), each in its
// struct's namespace. A kind's own structs list theirs beside the kind.
#pragma once

#include "analysis/common/cutting_coefficients.h"
#include "analysis/common/modal_parameters.h"
#include "analysis/cutting/dyno_slot.h"
#include "analysis/cutting/slot_fit.h"
#include "analysis/frf/modal_fit.h"
#include "analysis/frf/mode.h"
#include "app/core/archive.h"

namespace chatterlab {

template <class Ar>
void fields(Ar& ar, ModalParameters& p) {
  LAYOUT_GUARD(ModalParameters, 24);
  ar(p.m_kg, p.c_kg_s, p.k_N_m);
}

template <class Ar>
void fields(Ar& ar, CuttingCoefficients& k) {
  LAYOUT_GUARD(CuttingCoefficients, 32);
  ar(k.Kt_N_m2, k.Kr_N_m2, k.Kte_N_m, k.Kre_N_m);
}

namespace cutting {

template <class Ar>
void fields(Ar& ar, SlotRecordResult& r) {
  LAYOUT_GUARD(SlotRecordResult, 224);
  ar(r.summary, r.theta_dyn_rad, r.mean_Ft_N, r.mean_Fr_N, r.revolutions, r.measured_rpm,
     r.offset_x_N, r.offset_y_N, r.switching_contrast, r.per_revolution_Ft_N, r.per_revolution_Fr_N,
     r.spread_Ft_N, r.spread_Fr_N);
}

template <class Ar>
void fields(Ar& ar, FittedLine& l) {
  LAYOUT_GUARD(FittedLine, 32);
  ar(l.slope_N_per_m2, l.intercept_N_per_m, l.rms_residual_N, l.r_squared);
}

template <class Ar>
void fields(Ar& ar, SlotCoefficients& c) {
  LAYOUT_GUARD(SlotCoefficients, 208);
  ar(c.summary, c.coefficients, c.tangential, c.radial, c.mean_force_model, c.records,
     c.distinct_feeds);
}

}  // namespace cutting

namespace frf {

template <class Ar>
void fields(Ar& ar, Mode& m) {
  LAYOUT_GUARD(Mode, 40);
  fields(ar, static_cast<ModalParameters&>(m));
  ar(m.fn_hz, m.zeta);
}

template <class Ar>
void fields(Ar& ar, ModeQuality& q) {
  LAYOUT_GUARD(ModeQuality, 24);
  ar(q.resolution_limited, q.half_power_bins, q.negative_constant, q.at_bound, q.from_residual);
}

}  // namespace frf
}  // namespace chatterlab
