// Scratch shared by the callers that use it one at a time (docs/architecture.md "Memory").
//
// Full-frame working buffers that live only inside one call (a metric's preparations, the
// output being formed by a post pass, a cell's tone-mapped image) are lent from a pool instead
// of being held by every cell, method or stream. A lease gives a reused object if one is free
// and makes one otherwise; the pool keeps every object it made. So the scratch held grows with
// how many calls ran at once (the threads, when the callers run in parallel) and not with how
// many cells or streams exist, and nothing is allocated per frame once the pool is warm.
//
// A lent object keeps what the previous user left in it: users that reuse a preparation across
// calls must check it (MetricsScratch compares the pixels it was prepared from).
#pragma once
#include <cstddef>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

namespace fovsim {

template <class T>
class ScratchPool {
 public:
  class Lease {
   public:
    Lease(ScratchPool* pool, std::unique_ptr<T> obj) : pool_(pool), obj_(std::move(obj)) {}
    Lease(Lease&& o) noexcept : pool_(o.pool_), obj_(std::move(o.obj_)) { o.pool_ = nullptr; }
    Lease(const Lease&) = delete;
    Lease& operator=(const Lease&) = delete;
    Lease& operator=(Lease&&) = delete;
    ~Lease() {
      if (pool_ && obj_) pool_->give_back(std::move(obj_));
    }
    T& operator*() const { return *obj_; }
    T* operator->() const { return obj_.get(); }
    T* get() const { return obj_.get(); }

   private:
    ScratchPool* pool_;
    std::unique_ptr<T> obj_;
  };

  ScratchPool() = default;
  ScratchPool(const ScratchPool&) = delete;
  ScratchPool& operator=(const ScratchPool&) = delete;

  // The most recently returned free object (its buffers are the warmest), else a new one.
  Lease take() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!free_.empty()) {
        std::unique_ptr<T> o = std::move(free_.back());
        free_.pop_back();
        return Lease(this, std::move(o));
      }
      ++made_;
    }
    return Lease(this, std::make_unique<T>());
  }
  // Objects made so far: the most that were lent at once.
  size_t made() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return made_;
  }
  // Frees the objects not lent now (the next lease makes a new one).
  void clear() {
    std::lock_guard<std::mutex> lock(mutex_);
    made_ -= free_.size();
    free_.clear();
  }

 private:
  void give_back(std::unique_ptr<T> o) {
    std::lock_guard<std::mutex> lock(mutex_);
    free_.push_back(std::move(o));
  }
  mutable std::mutex mutex_;
  std::vector<std::unique_ptr<T>> free_;
  size_t made_ = 0;
};

}  // namespace fovsim
