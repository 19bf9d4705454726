#pragma once
// A pause point for the studio's tests (ServerOptions::pause_hook): events ordered by the
// server's own named points, never by the clock. Every wait is bounded (a broken server fails the
// test instead of hanging it).

#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <string_view>

namespace gridshell::test {

class StudioGate {
 public:
  /// The hook to put in ServerOptions::pause_hook (the gate must outlive the server).
  std::function<void(std::string_view)> hook() {
    return [this](std::string_view point) { hit(point); };
  }
  /// Pause at the n-th "check" from now on (counting from the checks seen so far), or at the
  /// n-th "queued" when `at_queued`.
  void pause_at(int n, bool at_queued = false) {
    std::lock_guard lock(m_);
    pause_check_ = at_queued ? -1 : checks_ + n;
    pause_queued_ = at_queued ? queued_ + n : -1;
    paused_ = released_ = false;
  }
  void release() {
    std::lock_guard lock(m_);
    released_ = true;
    cv_.notify_all();
  }
  /// Waits (at most `seconds`) until the server stands at the pause point.
  bool wait_paused(double seconds = 300) {
    std::unique_lock lock(m_);
    return cv_.wait_for(lock, std::chrono::duration<double>(seconds), [this] { return paused_; });
  }
  /// Waits until `n` requests in all have been queued.
  bool wait_queued(int n, double seconds = 300) {
    std::unique_lock lock(m_);
    return cv_.wait_for(lock, std::chrono::duration<double>(seconds),
                        [this, n] { return queued_ >= n; });
  }
  int checks() {
    std::lock_guard lock(m_);
    return checks_;
  }
  int queued() {
    std::lock_guard lock(m_);
    return queued_;
  }

 private:
  void hit(std::string_view point) {
    std::unique_lock lock(m_);
    const bool check = point == "check";
    const int n = check ? ++checks_ : ++queued_;
    cv_.notify_all();
    if (n == (check ? pause_check_ : pause_queued_)) {
      paused_ = true;
      cv_.notify_all();
      cv_.wait_for(lock, std::chrono::minutes(10), [this] { return released_; });
    }
  }
  std::mutex m_;
  std::condition_variable cv_;
  int checks_ = 0, queued_ = 0, pause_check_ = -1, pause_queued_ = -1;
  bool paused_ = false, released_ = false;
};

}  // namespace gridshell::test
