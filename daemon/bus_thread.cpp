// The handling timeout bounds how long stop() waits; messages are handled as they arrive.
#include "daemon/bus_thread.hpp"

#include <pthread.h>

#include <chrono>

namespace ccdlane {

void BusThread::start() {
  if (thread_.joinable()) return;
  stop_.store(false, std::memory_order_relaxed);
  thread_ = std::thread([this] { loop(); });
}

void BusThread::stop() {
  stop_.store(true, std::memory_order_release);
  if (thread_.joinable()) thread_.join();
}

void BusThread::loop() {
  pthread_setname_np(pthread_self(), "ccd-bus");
  while (!stop_.load(std::memory_order_acquire)) {
    if (lcm_handle_timeout(lcm_, kWaitMs) < 0) {
      errors_.fetch_add(1, std::memory_order_relaxed);
      std::this_thread::sleep_for(std::chrono::milliseconds(kWaitMs));
    }
  }
}

}  // namespace ccdlane
