#pragma once
/// \file once_map.h
/// Values computed once per key and shared between threads: the first caller of `get` for a key
/// computes the value, inside an isolated TBB region (a caller waiting for a nested parallel
/// loop must not pick up other work that waits for the same value); the others wait for it and
/// get the same object. What designs of one surface share (DesignCache, pipeline/design.h)
/// lives in these.

#include <map>
#include <memory>
#include <mutex>

#include <tbb/task_arena.h>

namespace gridshell {

/// Values computed once per key, thread-safe. A value, once made, never moves or changes.
template <class Key, class Value>
class OnceMap {
 public:
  template <class Make>
  const Value& get(const Key& key, Make&& make) {
    std::shared_ptr<Slot> slot;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      std::shared_ptr<Slot>& s = slots_[key];
      if (!s) s = std::make_shared<Slot>();
      slot = s;
    }
    std::call_once(slot->once,
                   [&] { tbb::this_task_arena::isolate([&] { slot->value = make(); }); });
    return slot->value;
  }

 private:
  struct Slot {
    std::once_flag once;
    Value value;
  };
  std::mutex mutex_;
  std::map<Key, std::shared_ptr<Slot>> slots_;
};

}  // namespace gridshell
