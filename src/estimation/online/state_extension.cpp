#include "inertial/estimation/online/state_extension.hpp"

#include <map>

namespace inertial {

namespace {

// Index of every name, or nullopt (and *why) for a name given twice or a list not of x's size.
std::optional<std::map<std::string, int>> IndexNames(const std::vector<std::string>& names, Eigen::Index size,
                                                     const char* which, std::string* why) {
  if (static_cast<Eigen::Index>(names.size()) != size) {
    if (why != nullptr) {
      *why = std::string("the ") + which + " state has " + std::to_string(size) + " entries but " +
             std::to_string(names.size()) + " names";
    }
    return std::nullopt;
  }
  std::map<std::string, int> index;
  for (size_t i = 0; i < names.size(); ++i) {
    if (!index.emplace(names[i], static_cast<int>(i)).second) {
      if (why != nullptr) *why = std::string("the ") + which + " state names '" + names[i] + "' twice";
      return std::nullopt;
    }
  }
  return index;
}

bool CovarianceFits(const EstimatorState& s) {
  return s.P.size() == 0 || (s.P.rows() == s.x.size() && s.P.cols() == s.x.size());
}

}  // namespace

std::optional<ExtendedState> ExtendEstimatorState(const EstimatorState& saved, const std::vector<std::string>& saved_names,
                                                  const EstimatorState& fresh, const std::vector<std::string>& fresh_names,
                                                  std::string* why) {
  if (saved.kind != fresh.kind) {
    if (why != nullptr) *why = "the saved state is of a '" + saved.kind + "' estimator, this one is '" + fresh.kind + "'";
    return std::nullopt;
  }
  const auto saved_index = IndexNames(saved_names, saved.x.size(), "saved", why);
  if (!saved_index) return std::nullopt;
  const auto fresh_index = IndexNames(fresh_names, fresh.x.size(), "new", why);
  if (!fresh_index) return std::nullopt;
  if (!CovarianceFits(saved) || !CovarianceFits(fresh) || (saved.P.size() == 0) != (fresh.P.size() == 0)) {
    if (why != nullptr) *why = "the covariances do not match the parameters (one state has one, the other none, or of another size)";
    return std::nullopt;
  }
  // Where each saved entry goes; every missing name is listed.
  std::vector<int> to(saved_names.size());
  std::string missing;
  int num_missing = 0;
  for (size_t i = 0; i < saved_names.size(); ++i) {
    const auto it = fresh_index->find(saved_names[i]);
    if (it == fresh_index->end()) {
      missing += (missing.empty() ? "'" : ", '") + saved_names[i] + "'";
      ++num_missing;
    } else {
      to[i] = it->second;
    }
  }
  if (num_missing > 0) {
    if (why != nullptr) {
      *why = std::string(num_missing == 1 ? "parameter " : "parameters ") + missing + " of the saved state " +
             (num_missing == 1 ? "is" : "are") + " not in this model";
    }
    return std::nullopt;
  }

  ExtendedState out;
  out.state = fresh;
  EstimatorState& s = out.state;
  std::vector<bool> is_saved(fresh_names.size(), false);
  for (size_t i = 0; i < to.size(); ++i) is_saved[static_cast<size_t>(to[i])] = true;
  for (size_t k = 0; k < fresh_names.size(); ++k) {
    if (!is_saved[k]) out.added.push_back(fresh_names[k]);
  }
  const Eigen::Index n = static_cast<Eigen::Index>(to.size());
  for (Eigen::Index i = 0; i < n; ++i) s.x[to[static_cast<size_t>(i)]] = saved.x[i];
  if (s.P.size() > 0) {
    // Cross-covariances of new with saved entries: zero.
    for (Eigen::Index k = 0; k < s.P.rows(); ++k) {
      if (is_saved[static_cast<size_t>(k)]) continue;
      for (Eigen::Index i = 0; i < n; ++i) {
        s.P(k, to[static_cast<size_t>(i)]) = 0.0;
        s.P(to[static_cast<size_t>(i)], k) = 0.0;
      }
    }
    for (Eigen::Index j = 0; j < n; ++j) {
      for (Eigen::Index i = 0; i < n; ++i) s.P(to[static_cast<size_t>(i)], to[static_cast<size_t>(j)]) = saved.P(i, j);
    }
  }
  s.has_time = saved.has_time;
  s.last_time = saved.last_time;
  s.counters = saved.counters;
  return out;
}

}  // namespace inertial
