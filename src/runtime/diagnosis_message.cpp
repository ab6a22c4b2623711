#include "inertial/runtime/diagnosis_message.hpp"

#include <cmath>

#include "inertial/diagnosis_t.hpp"
#include "inertial/payload_event_t.hpp"
#include "inertial/report/online_diagnosis_report.hpp"

namespace inertial {

std::vector<std::uint8_t> EncodeDiagnosis(const OnlineDiagnosisResult& r, std::int64_t utime) {
  inertial::diagnosis_t m;
  m.utime = utime;
  m.window = r.window_seconds;
  m.samples = r.samples;
  m.rms = r.model.total_rms;
  for (const OnlineCandidate& c : r.candidates) {
    if (!c.evidence.suggested() || !c.alternative_to.empty()) continue;
    m.effect.push_back(std::string(ToString(c.kind)));
    m.target.push_back(c.joint.empty() ? c.link : c.joint);
    m.item.push_back(c.item);
    m.explained.push_back(c.evidence.explained);
    m.restored.push_back(c.evidence.restored);
    m.explanation.push_back(OnlineCandidateExplanation(c));
  }
  m.num_suggestions = static_cast<std::int32_t>(m.effect.size());
  m.bent_links = r.bent_links;
  m.num_bent = static_cast<std::int32_t>(m.bent_links.size());
  std::vector<std::uint8_t> bytes(static_cast<size_t>(m.getEncodedSize()));
  m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

std::vector<std::uint8_t> EncodePayloadEvent(const PayloadEvent& e) {
  inertial::payload_event_t m;
  auto us = [](double t) { return static_cast<std::int64_t>(std::llround(t * 1e6)); };
  m.utime = us(e.detection_time);
  m.onset_utime = us(e.onset_time);
  m.settle_utime = us(e.settle_time);
  m.settled = e.settled;
  m.link = e.link;
  m.added_mass = e.added_mass;
  m.added_mass_std = e.added_mass_std;
  for (int i = 0; i < 3; ++i) {
    m.com[i] = e.com[i];
    m.com_std[i] = e.com_std[i];
  }
  for (int i = 0; i < 10; ++i) m.added_pi[i] = e.added_pi[i];
  m.statistic = e.statistic;
  m.threshold = e.threshold;
  m.kappa = e.kappa;
  m.runner_up_margin = e.runner_up_margin;
  m.runner_up_link = e.runner_up_link;
  m.num_samples = e.num_samples;
  std::vector<std::uint8_t> bytes(static_cast<size_t>(m.getEncodedSize()));
  m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

}  // namespace inertial
