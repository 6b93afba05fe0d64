#pragma once

// The two handles on a pool slot.
//
//  - Loan<T>: the writer's handle, from Publisher<T>::loan(). Move-only, mutable access.
//    Consumed by Publisher<T>::publish(); a loan dropped unpublished goes back to the pool.
//    A fresh loan holds what the slot's last user left (vectors keep their capacity):
//    the writer sets every field it publishes. Only the header is reset by loan().
//  - Sample<T>: a reader's handle, given to subscription callbacks. Read-only. Copying
//    it shares the slot (a reference count, no allocation); the slot returns to the
//    pool when the last Sample and the last queue entry pointing at it are gone.
//
// Every subscriber of a publish receives a Sample on the same slot: no copy, whatever
// the payload size. Neither handle may outlive the topic (its pool checks this).

#include <cstdint>
#include <utility>

#include "executors/sample_pool.hpp"

namespace scancrew {

template <class T>
class Loan {
 public:
  Loan() = default;
  Loan(SamplePool<T>* pool, uint32_t index) : pool_(pool), index_(index) {}
  Loan(const Loan&) = delete;
  Loan& operator=(const Loan&) = delete;
  Loan(Loan&& other) noexcept : pool_(std::exchange(other.pool_, nullptr)), index_(other.index_) {}
  Loan& operator=(Loan&& other) noexcept {
    if (this != &other) {
      reset();
      pool_ = std::exchange(other.pool_, nullptr);
      index_ = other.index_;
    }
    return *this;
  }
  ~Loan() { reset(); }

  bool valid() const { return pool_ != nullptr; }
  T& operator*() { return pool_->at(index_); }
  T* operator->() { return &pool_->at(index_); }
  const T& operator*() const { return pool_->at(index_); }
  const T* operator->() const { return &pool_->at(index_); }

  // Hands the slot (and its reference) to the caller; the loan becomes invalid.
  uint32_t release_to_publish() {
    pool_ = nullptr;
    return index_;
  }
  const SamplePool<T>* pool() const { return pool_; }

 private:
  void reset() {
    if (pool_ != nullptr) std::exchange(pool_, nullptr)->release(index_);
  }
  SamplePool<T>* pool_ = nullptr;
  uint32_t index_ = 0;
};

template <class T>
class Sample {
 public:
  Sample() = default;
  // Adopts one reference on the slot.
  Sample(SamplePool<T>* pool, uint32_t index) : pool_(pool), index_(index) {}
  Sample(const Sample& other) : pool_(other.pool_), index_(other.index_) {
    if (pool_ != nullptr) pool_->retain(index_);
  }
  Sample& operator=(const Sample& other) {
    if (this != &other) {
      if (other.pool_ != nullptr) other.pool_->retain(other.index_);
      reset();
      pool_ = other.pool_;
      index_ = other.index_;
    }
    return *this;
  }
  Sample(Sample&& other) noexcept
      : pool_(std::exchange(other.pool_, nullptr)), index_(other.index_) {}
  Sample& operator=(Sample&& other) noexcept {
    if (this != &other) {
      reset();
      pool_ = std::exchange(other.pool_, nullptr);
      index_ = other.index_;
    }
    return *this;
  }
  ~Sample() { reset(); }

  bool valid() const { return pool_ != nullptr; }
  const T& operator*() const { return pool_->at(index_); }
  const T* operator->() const { return &pool_->at(index_); }
  const T* get() const { return pool_ == nullptr ? nullptr : &pool_->at(index_); }

  void reset() {
    if (pool_ != nullptr) std::exchange(pool_, nullptr)->release(index_);
  }

 private:
  SamplePool<T>* pool_ = nullptr;
  uint32_t index_ = 0;
};

}  // namespace scancrew
