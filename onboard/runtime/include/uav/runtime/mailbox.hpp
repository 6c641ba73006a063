#pragma once
// The hand-over shapes between onboard threads, each with its own lock: the newest value
// (Latest), every value in order (Queue, optionally bounded), the newest value per key in the
// order keys first waited (KeyedLatest), and one Latest per vehicle report (ReportSlots).
#include <cstddef>
#include <deque>
#include <iterator>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <tuple>
#include <type_traits>
#include <vector>

#include "uav/shared/reports.hpp"

namespace uav::runtime {

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

// One Latest<T> per type T of a TypeList: Put(report), Take<T>(). Beside them, every report's
// signals (ReportSignals<T>) as the flight log's columns: named "<GROUP>.<signal>", in the list's
// order, holding the newest report's values (NaN before its first).
template <class List>
class ReportSlots;
template <class... Ts>
class ReportSlots<TypeList<Ts...>> {
 public:
  template <class T>
  void Put(T report) {
    const auto& table = ReportSignals<T>::Table();
    if (!table.empty()) {
      std::lock_guard<std::mutex> lock(columns_mutex_);
      double* out = columns_.data() + Offset<T>();
      for (const auto& s : table) *out++ = s.read(report);
    }
    std::get<Latest<T>>(slots_).Put(std::move(report));
  }
  template <class T>
  std::optional<T> Take() {
    return std::get<Latest<T>>(slots_).Take();
  }

  static const std::vector<std::string>& ColumnNames() {
    static const std::vector<std::string> k = [] {
      std::vector<std::string> names;
      auto add = [&](auto* type) {
        using T = std::remove_pointer_t<decltype(type)>;
        for (const auto& s : ReportSignals<T>::Table())
          names.push_back(std::string(ReportSignals<T>::kGroup) + "." + std::string(s.def.name));
      };
      (add(static_cast<Ts*>(nullptr)), ...);
      return names;
    }();
    return k;
  }
  static const std::vector<SignalDef>& ColumnDefs() {
    static const std::vector<SignalDef> k = [] {
      std::vector<SignalDef> defs;
      auto add = [&](auto* type) {
        for (const auto& s : ReportSignals<std::remove_pointer_t<decltype(type)>>::Table()) defs.push_back(s.def);
      };
      (add(static_cast<Ts*>(nullptr)), ...);
      return defs;
    }();
    return k;
  }
  std::vector<double> Columns() const {
    std::lock_guard<std::mutex> lock(columns_mutex_);
    return columns_;
  }

 private:
  // Where T's columns start.
  template <class T>
  static std::size_t Offset() {
    static const std::size_t k = [] {
      std::size_t offset = 0;
      bool before = true;
      auto step = [&](auto* type) {
        using U = std::remove_pointer_t<decltype(type)>;
        before = before && !std::is_same_v<T, U>;
        if (before) offset += ReportSignals<U>::Table().size();
      };
      (step(static_cast<Ts*>(nullptr)), ...);
      return offset;
    }();
    return k;
  }

  std::tuple<Latest<Ts>...> slots_;
  mutable std::mutex columns_mutex_;
  std::vector<double> columns_ = std::vector<double>(ColumnNames().size(), std::numeric_limits<double>::quiet_NaN());
};

}  // namespace uav::runtime
