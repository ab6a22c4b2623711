// daemon_probe: the latency of a running inertiald, from outside, the same for any build of it.
// Plays the joint states of an LCM log (as lcm-logplayer would, paced by the events' time stamps,
// optionally faster) on an LCM URL, and listens to the estimates the daemon publishes. Each sample
// is keyed by its event time stamp (inertial simulate --write-log writes the sample time there, in
// microseconds, and the daemon's estimate_t.utime is the time of the last sample it used), so an
// estimate received at T with utime u publishes every sample with time <= u not yet published:
// their latency is T minus the moment the probe handed them to LCM. Prints one JSON line:
// published, estimates received, samples whose estimate came, and latency percentiles [ms].
//   daemon_probe --log leg.lcm --url URL [--speed 1] [--seconds 20] [--channel C] [--estimate-channel E]
//   [--skip S]: percentiles of the samples after the log's first S seconds (default 1: the warm-up)
//   [--dump FILE]: each sample's time in the log [s] and latency [ms], a line each
//   daemon_probe --count leg.lcm [--channel C]      the number of events on the channel
// The estimate's utime is read from its bytes (the first field after the 8-byte fingerprint), not
// through a generated type, so that builds whose estimate_t differ in later fields both decode.
#include <lcm/lcm-cpp.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;

struct Event {
  std::int64_t utime;
  std::vector<std::uint8_t> data;
};

std::vector<Event> ReadEvents(const std::string& path, const std::string& channel, double seconds) {
  lcm::LogFile log(path, "r");
  if (!log.good()) throw std::runtime_error("cannot read " + path);
  std::vector<Event> events;
  for (const lcm::LogEvent* ev = log.readNextEvent(); ev != nullptr; ev = log.readNextEvent()) {
    if (ev->channel != channel) continue;
    if (seconds > 0 && !events.empty() && ev->timestamp - events.front().utime >= static_cast<std::int64_t>(seconds * 1e6)) {
      break;
    }
    const auto* d = static_cast<const std::uint8_t*>(ev->data);
    events.push_back({ev->timestamp, std::vector<std::uint8_t>(d, d + ev->datalen)});
  }
  return events;
}

double Percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  const auto k = static_cast<size_t>(std::min<double>(static_cast<double>(v.size()) - 1, p * static_cast<double>(v.size())));
  std::nth_element(v.begin(), v.begin() + static_cast<long>(k), v.end());
  return v[k];
}

struct Listener {
  const std::vector<Event>* events = nullptr;
  std::vector<Clock::time_point> sent;
  std::atomic<size_t> published{0};
  std::mutex mutex;
  size_t next = 0;  // the first sample whose estimate has not come
  std::vector<double> latency_ms;
  std::uint64_t estimates = 0;

  void Handle(const lcm::ReceiveBuffer* rbuf, const std::string&) {
    const Clock::time_point now = Clock::now();
    if (rbuf->data_size < 16) return;
    const auto* b = static_cast<const std::uint8_t*>(rbuf->data) + 8;
    std::uint64_t u = 0;
    for (int i = 0; i < 8; ++i) u = (u << 8) | b[i];
    const auto utime = static_cast<std::int64_t>(u);
    const size_t sent_so_far = published.load(std::memory_order_acquire);
    std::lock_guard<std::mutex> lock(mutex);
    ++estimates;
    while (next < sent_so_far && (*events)[next].utime <= utime) {
      latency_ms.push_back(std::chrono::duration<double, std::milli>(now - sent[next]).count());
      ++next;
    }
  }
};

}  // namespace

int main(int argc, char** argv) {
  std::map<std::string, std::string> a;
  for (int i = 1; i + 1 < argc; i += 2) a[argv[i]] = argv[i + 1];
  const std::string channel = a.count("--channel") ? a["--channel"] : "INERTIAL_JOINT_STATE";
  try {
    if (a.count("--count")) {
      std::cout << ReadEvents(a["--count"], channel, 0).size() << "\n";
      return 0;
    }
    if (!a.count("--log") || !a.count("--url")) {
      std::cerr << "usage: daemon_probe --log FILE --url URL [--speed S] [--seconds T] | --count FILE\n";
      return 2;
    }
    const double speed = a.count("--speed") ? std::stod(a["--speed"]) : 1.0;
    const double seconds = a.count("--seconds") ? std::stod(a["--seconds"]) : 0.0;
    const std::string estimates = a.count("--estimate-channel") ? a["--estimate-channel"] : "INERTIAL_ESTIMATE";
    const std::vector<Event> events = ReadEvents(a["--log"], channel, seconds);
    lcm::LCM lcm(a["--url"]);
    if (!lcm.good()) throw std::runtime_error("LCM cannot start on " + a["--url"]);
    Listener listener;
    listener.events = &events;
    listener.sent.resize(events.size());
    listener.latency_ms.reserve(events.size());
    lcm.subscribe(estimates, &Listener::Handle, &listener);
    std::atomic<bool> stop{false};
    std::thread receiver([&] {
      while (!stop) lcm.handleTimeout(20);
    });
    const Clock::time_point start = Clock::now() + std::chrono::milliseconds(100);
    for (size_t i = 0; i < events.size(); ++i) {
      const auto offset = std::chrono::duration<double, std::micro>(static_cast<double>(events[i].utime - events[0].utime) / speed);
      std::this_thread::sleep_until(start + std::chrono::duration_cast<Clock::duration>(offset));
      listener.sent[i] = Clock::now();
      listener.published.store(i + 1, std::memory_order_release);
      lcm.publish(channel, events[i].data.data(), static_cast<unsigned>(events[i].data.size()));
    }
    std::this_thread::sleep_for(std::chrono::seconds(1));  // the last estimates
    stop = true;
    receiver.join();
    std::lock_guard<std::mutex> lock(listener.mutex);
    const std::vector<double>& l = listener.latency_ms;
    // The percentiles leave out the first --skip seconds of the log (default 1): while the online
    // fit warms up it holds samples until its first solve, and the estimate's time stays at the
    // last accepted one, which is the estimator's start, not the loop's latency.
    const double skip = a.count("--skip") ? std::stod(a["--skip"]) : 1.0;
    std::vector<double> kept;
    for (size_t i = 0; i < l.size(); ++i) {
      if (static_cast<double>(events[i].utime - events[0].utime) * 1e-6 >= skip) kept.push_back(l[i]);
    }
    if (a.count("--dump")) {  // one line per sample: its time in the log [s], its latency [ms]
      std::FILE* f = std::fopen(a["--dump"].c_str(), "w");
      for (size_t i = 0; f != nullptr && i < l.size(); ++i) {
        std::fprintf(f, "%.3f %.3f\n", static_cast<double>(events[i].utime - events[0].utime) * 1e-6, l[i]);
      }
      if (f != nullptr) std::fclose(f);
    }
    std::printf(
        "{\"published\": %zu, \"estimates\": %llu, \"samples_with_estimate\": %zu, \"p50_ms\": %.3f, \"p99_ms\": %.3f, "
        "\"p999_ms\": %.3f, \"max_ms\": %.3f}\n",
        events.size(), static_cast<unsigned long long>(listener.estimates), l.size(), Percentile(kept, 0.5),
        Percentile(kept, 0.99), Percentile(kept, 0.999), kept.empty() ? 0.0 : *std::max_element(kept.begin(), kept.end()));
  } catch (const std::exception& e) {
    std::cerr << "daemon_probe: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
