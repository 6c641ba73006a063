#pragma once
// The hand-over shapes between onboard threads, each with its own lock: the newest value
// (Latest), every value in order (Queue, optionally bounded), the newest value per key in the
// order keys first waited (KeyedLatest), and one Latest per perception report (ReportSlots).
#include <cstddef>
#include <deque>
#include <iterator>
#include <map>
#include <mutex>
#include <optional>
#include <tuple>
#include <vector>

#include "uav/shared/reports.hpp"

namespace uav::app {

// The newest value replaces one not yet taken (results are live, not queued).
template <class T>
class Latest {
 public:
  void Put(T v) {
    std::lock_guard<std::mutex> lock(mutex_);
    value_ = std::move(v);
  }
  std::optional<T> Take() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::optional<T> out = std::move(value_);
    value_.reset();
    return out;
  }

 private:
  std::mutex mutex_;
  std::optional<T> value_;
};

// Every value, in order. Bounded (capacity > 0): the oldest goes when a new one would exceed it.
template <class T>
class Queue {
 public:
  explicit Queue(std::size_t capacity = 0) : capacity_(capacity) {}
  void Push(T v) {
    std::lock_guard<std::mutex> lock(mutex_);
    items_.push_back(std::move(v));
    while (capacity_ > 0 && items_.size() > capacity_) items_.pop_front();
  }
  void PushAll(const std::vector<T>& vs) {
    for (const T& v : vs) Push(v);
  }
  std::vector<T> TakeAll() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<T> out(std::make_move_iterator(items_.begin()), std::make_move_iterator(items_.end()));
    items_.clear();
    return out;
  }

 private:
  std::mutex mutex_;
  std::size_t capacity_;
  std::deque<T> items_;
};

// Per key, the newest value replaces the one still waiting; keys are taken in the order they
// started waiting (the longest-waiting first).
template <class K, class T>
class KeyedLatest {
 public:
  void Put(const K& key, T v) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!values_.count(key)) order_.push_back(key);
    values_.insert_or_assign(key, std::move(v));
  }
  std::optional<T> TakeOldest() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (order_.empty()) return std::nullopt;
    const K key = order_.front();
    order_.pop_front();
    auto it = values_.find(key);
    T out = std::move(it->second);
    values_.erase(it);
    return out;
  }
  std::vector<T> TakeAll() {
    std::vector<T> out;
    while (auto v = TakeOldest()) out.push_back(std::move(*v));
    return out;
  }

 private:
  std::mutex mutex_;
  std::map<K, T> values_;
  std::deque<K> order_;
};

// One Latest<T> per type T of a TypeList: Put(report), Take<T>().
template <class List>
class ReportSlots;
template <class... Ts>
class ReportSlots<TypeList<Ts...>> {
 public:
  template <class T>
  void Put(T report) {
    std::get<Latest<T>>(slots_).Put(std::move(report));
  }
  template <class T>
  std::optional<T> Take() {
    return std::get<Latest<T>>(slots_).Take();
  }

 private:
  std::tuple<Latest<Ts>...> slots_;
};

}  // namespace uav::app
