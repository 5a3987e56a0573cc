// The estimator table (ekf_variants.h): every derived function agrees with it, and its estimate
// keys are the keys each variant actually reports.
#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

#include "analysis/estimate/ekf_variants.h"
#include "tests/support/estimators_run.h"

namespace chatterlab {
namespace estimate {
namespace {

TEST(EstimatorTable, DerivedFunctionsFollowTheTable) {
  // all_estimators() lists each id once, in enum order; names are unique and round-trip.
  const auto ids = all_estimators();
  ASSERT_EQ(ids.size(), 13u);
  std::set<std::string> names;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    EXPECT_EQ(static_cast<std::size_t>(ids[i]), i);
    const EstimatorInfo& e = estimator_info(ids[i]);
    EXPECT_EQ(e.id, ids[i]);
    EXPECT_STREQ(estimator_name(ids[i]), e.name);
    EXPECT_EQ(estimator_from_name(e.name), ids[i]);
    EXPECT_EQ(estimator_states(ids[i]), e.states);
    EXPECT_EQ(is_modal(ids[i]), e.modal);
    // The first six are the EKFs of EXPERIMENT_FORMAT.md; the next six their unscented twins,
    // named "ukf-" + the twin's name without "ekf-", with the same states and keys; the last
    // the feedback filter on the per-tooth model.
    const EstimatorId twin = structure_of(ids[i]);
    EXPECT_EQ(is_unscented(ids[i]), i >= 6 && i < 12);
    EXPECT_EQ(estimate_keys(ids[i], 2), estimate_keys(twin, 2));
    EXPECT_EQ(estimator_states(ids[i]), estimator_states(twin));
    if (i < 12) {
      EXPECT_EQ(static_cast<std::size_t>(twin), i % 6);
      EXPECT_EQ(std::string(e.name),
                (i >= 6 ? "ukf-" : "ekf-") + std::string(estimator_name(twin)).substr(4));
      EXPECT_STREQ(filter_name(ids[i]), i >= 6 ? "unscented" : "extended");
    } else {
      EXPECT_EQ(twin, EstimatorId::kCoeffXyPerTooth);
      EXPECT_STREQ(e.name, "ekf-coeff-xy-feedback");
      EXPECT_STREQ(filter_name(ids[i]), "extended-feedback");
    }
    names.insert(e.name);
  }
  EXPECT_EQ(names.size(), ids.size());
  // Constant expressions: usable where the app needs a compile-time list.
  static_assert(estimator_states(EstimatorId::kModalXy) == 7);
  static_assert(!is_modal(EstimatorId::kCoeffXyPerTooth));
}

TEST(EstimatorTable, EstimateKeys) {
  EXPECT_EQ(estimate_keys(EstimatorId::kModalX),
            (std::vector<std::string>{"m_kg", "c_kg_s", "k_N_m"}));
  EXPECT_EQ(estimate_keys(EstimatorId::kModalXyMk), (std::vector<std::string>{"m_kg", "k_N_m"}));
  EXPECT_EQ(estimate_keys(EstimatorId::kModalXyMc), (std::vector<std::string>{"m_kg", "c_kg_s"}));
  EXPECT_EQ(estimate_keys(EstimatorId::kCoeffXy), (std::vector<std::string>{"Kt_N_m2", "Kr_N_m2"}));
  EXPECT_EQ(estimate_keys(EstimatorId::kCoeffXyPerTooth, 3),
            (std::vector<std::string>{"Kt1_N_m2", "Kr1_N_m2", "Kt2_N_m2", "Kr2_N_m2", "Kt3_N_m2",
                                      "Kr3_N_m2"}));
  try {
    estimate_keys(EstimatorId::kCoeffXyPerTooth, 0);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "estimate_keys: teeth = 0: must be >= 1");
  }
}

TEST(EstimatorTable, KeysAreWhatEachVariantReports) {
  // Every variant on a short cut (0.01 s): its EkfResult::estimates carry exactly the table's
  // keys, in order, and its history the deflection states then those keys.
  const MeasuredCut& cut = chatterlab::testing::estimators_short_cut();
  const CutSetup setup;
  for (EstimatorId id : all_estimators()) {
    const EkfResult r = chatterlab::testing::run_estimator(id, cut, setup);
    ASSERT_TRUE(r.summary.ok()) << estimator_name(id) << ": " << r.summary.message;
    const std::vector<std::string> keys = estimate_keys(id, setup.teeth);
    ASSERT_EQ(r.estimates.size(), keys.size()) << estimator_name(id);
    for (std::size_t j = 0; j < keys.size(); ++j) EXPECT_EQ(r.estimates[j].key, keys[j]);
    const std::size_t deflections = 2u * static_cast<std::size_t>(estimator_info(id).measured_axes);
    ASSERT_EQ(r.history.columns.size(), deflections + keys.size());
    for (std::size_t j = 0; j < keys.size(); ++j) {
      EXPECT_EQ(r.history.columns[deflections + j], keys[j]);
    }
    EXPECT_EQ(r.estimator, estimator_name(id));
  }
}

}  // namespace
}  // namespace estimate
}  // namespace chatterlab
