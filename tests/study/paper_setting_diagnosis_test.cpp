// The single-body diagnosis (body_diagnosis.hpp) in the paper's own setting (Section VI): 63
// samples at 0.1 s of a Table I body under the study's wrench, velocity noise uniform of width
// 0.05, with the paper's 0.1 velocity bias (its mean) or without it (clean). Over many seeded
// bodies: how often the bias is found where it is detectable, and how often a clean log raises a
// false alarm, with blocked 5-fold cross-validation (the default for short logs) against a single
// held-out split of 0.3.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "inertial/diagnosis/body_diagnosis.hpp"
#include "inertial/study/paper_study.hpp"

namespace inertial {
namespace {

constexpr std::uint64_t kSeed = 20261202;
constexpr int kBodies = 100;

InertialParams PaperPrior() {
  Vector10 pi;
  pi << 1, 0, 0, 0, 1, 1, 1, 0, 0, 0;
  return InertialParams::FromVector(pi);
}

BodyLog Log(const InertialParams& body, int index, double bias, double width) {
  StudyOptions options;
  options.noise_bias = bias;
  options.noise_width = width;
  BodyLog log;
  log.samples = SimulateStudyBody(body, kSeed, index, options);
  return log;
}

// Detectability, independent of the diagnosis's criteria: the part of the bias's wrench signature
// that no body can imitate (the residual of the best-fitting body without a bias on the noise-free
// biased log, eq. 13), against the residual the velocity noise alone causes (the true body on the
// unbiased noisy log). A bias whose unimitable signature is below the noise's cannot be told from
// it in 62 pairs.
double SignalToNoise(const InertialParams& body, int index) {
  const BodyEffectModel truth(body, {});
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(truth.num_parameters());  // theta = 0: the true body
  const BodyLog biased = Log(body, index, 0.1, 0.0);
  const BodyFit best = FitBodyModel(truth, biased, BodyDiagnosisOptions().fit);
  const double signal = truth.Residuals(best.x, biased).norm();
  const double noise = truth.Residuals(zero, Log(body, index, 0.0, 0.05)).norm();
  return signal / noise;
}

struct Rates {
  int detectable = 0, found = 0, found_any = 0, clean_alarms = 0;
};

template <typename DiagnoseFn>
Rates Measure(const DiagnoseFn& diagnose) {
  Rates r;
  for (int i = 0; i < kBodies; ++i) {
    const InertialParams body = SampleTableIBody(kSeed, i);
    const BodyDiagnosis biased = diagnose(Log(body, i, 0.1, 0.05));
    const BodyDiagnosis clean = diagnose(Log(body, i, 0.0, 0.05));
    if (clean.num_suggestions > 0) ++r.clean_alarms;
    const bool found = biased.num_suggestions > 0 && biased.candidates[0].kind == BodyEffectKind::kVelocityBias;
    if (found) ++r.found_any;
    if (SignalToNoise(body, i) >= 1.0) {
      ++r.detectable;
      if (found) ++r.found;
    }
  }
  return r;
}

TEST(PaperSettingDiagnosis, CrossValidationFindsTheBiasWithoutFalseAlarms) {
  const Rates cv = Measure([](const BodyLog& log) { return DiagnoseBodyModelCrossValidated(PaperPrior(), {}, log); });
  const Rates split = Measure([](const BodyLog& log) {
    BodyLog train, validation;
    SplitHoldout(log, 0.3, &train, &validation);
    return DiagnoseBodyModel(PaperPrior(), {}, train, validation);
  });
  std::cout << kBodies << " bodies; detectable (unimitable bias signature >= noise): " << cv.detectable << "\n"
            << "  5-fold cross-validation: found on " << cv.found << " of " << cv.detectable << " detectable ("
            << cv.found_any << " of " << kBodies << " biased logs), false alarms on " << cv.clean_alarms << " of "
            << kBodies << " clean logs\n"
            << "  0.3 held-out split:      found on " << split.found << " of " << split.detectable << " detectable ("
            << split.found_any << " of " << kBodies << "), false alarms on " << split.clean_alarms << " of " << kBodies
            << " clean logs\n";
  // The aim is every detectable bias and no false alarm; measured (seed above): 25 of 26 and 2 of
  // 100 (the split: 13 of 26 and 3 of 100). The bounds: at least 90 % of the detectable found, at
  // most 3 % false alarms (a 1 % rate would give 3 or more in 100 logs with probability 8 %), and
  // never worse than the single split.
  ASSERT_GE(cv.detectable, 10) << "too few detectable bodies for the rates to mean anything";
  EXPECT_GE(cv.found, 0.9 * cv.detectable);
  EXPECT_LE(cv.clean_alarms, 3);
  EXPECT_GE(cv.found, split.found);
  EXPECT_LE(cv.clean_alarms, split.clean_alarms);
}

TEST(PaperSettingDiagnosis, LogsTooShortToCrossValidateAreRefused) {
  BodyLog log = Log(SampleTableIBody(kSeed, 0), 0, 0.1, 0.05);
  log.samples.resize(15);  // 14 pairs: fewer than 5 folds of 4
  try {
    DiagnoseBodyModelCrossValidated(PaperPrior(), {}, log);
    FAIL() << "a 15-sample log was cross-validated";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("15 samples are too few for 5 folds (at least 21"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace inertial
