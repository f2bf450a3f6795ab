#pragma once
/// A byte format for results that cross process boundaries (system/distributed.hpp): numbers are
/// copied bit for bit (same machine type on every rank), so a result read back equals the
/// computed one exactly. Structs list their fields once in a `Wire<T>` specialisation:
///
///   template <> struct mg::system::Wire<MyResult> {
///     template <typename A> static void fields(A& a, MyResult& r) { a(r.x, r.outcome, r.name); }
///   };
///
/// Arithmetic types, enums, std::array, std::vector and std::string need none.
#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "core/error.hpp"
#include "sim/putt.hpp"

namespace mg::system {

template <typename T>
struct Wire;  ///< specialise for every struct sent between processes

namespace wire_detail {
template <typename T>
struct IsArray : std::false_type {};
template <typename T, std::size_t N>
struct IsArray<std::array<T, N>> : std::true_type {};
template <typename T>
struct IsVector : std::false_type {};
template <typename T, typename A>
struct IsVector<std::vector<T, A>> : std::true_type {};
}  // namespace wire_detail

class WireWriter {
 public:
  template <typename... T>
  void operator()(const T&... values) {
    (put(values), ...);
  }
  const std::string& bytes() const { return bytes_; }

 private:
  template <typename T>
  void put(const T& v) {
    if constexpr (std::is_arithmetic_v<T> || std::is_enum_v<T>) {
      bytes_.append(reinterpret_cast<const char*>(&v), sizeof v);
    } else if constexpr (wire_detail::IsArray<T>::value) {
      for (const auto& e : v) put(e);
    } else if constexpr (wire_detail::IsVector<T>::value || std::is_same_v<T, std::string>) {
      put(static_cast<std::uint64_t>(v.size()));
      for (const auto& e : v) put(e);
    } else {
      Wire<T>::fields(*this, const_cast<T&>(v));  // the writer only reads
    }
  }
  std::string bytes_;
};

class WireReader {
 public:
  explicit WireReader(std::string_view bytes) : bytes_(bytes) {}
  template <typename... T>
  void operator()(T&... values) {
    (get(values), ...);
  }
  bool at_end() const { return pos_ == bytes_.size(); }

 private:
  template <typename T>
  void get(T& v) {
    if constexpr (std::is_arithmetic_v<T> || std::is_enum_v<T>) {
      if (bytes_.size() - pos_ < sizeof v)
        throw Error("wire: a message from another process is truncated");
      std::memcpy(&v, bytes_.data() + pos_, sizeof v);
      pos_ += sizeof v;
    } else if constexpr (wire_detail::IsArray<T>::value) {
      for (auto& e : v) get(e);
    } else if constexpr (wire_detail::IsVector<T>::value || std::is_same_v<T, std::string>) {
      std::uint64_t n = 0;
      get(n);
      if (n > bytes_.size() - pos_)
        throw Error("wire: a message from another process is truncated");
      v.resize(static_cast<std::size_t>(n));
      for (auto& e : v) get(e);
    } else {
      Wire<T>::fields(*this, v);
    }
  }
  std::string_view bytes_;
  std::size_t pos_ = 0;
};

// The results of the system layer. The size checks catch a field added to a struct without
// adding it here (x86-64 layouts).
template <>
struct Wire<sim::BallSample> {
  static_assert(sizeof(sim::BallSample) == 56,
                "sim::BallSample changed: update Wire<sim::BallSample>");
  template <typename A>
  static void fields(A& a, sim::BallSample& s) {
    a(s.t, s.x, s.y, s.z, s.vx, s.vy, s.vz);
  }
};

template <>
struct Wire<sim::PuttOutcome> {
  static_assert(sizeof(sim::PuttOutcome) == 96,
                "sim::PuttOutcome changed: update Wire<sim::PuttOutcome>");
  template <typename A>
  static void fields(A& a, sim::PuttOutcome& o) {
    a(o.sunk, o.end, o.rest_position, o.closest_approach, o.approach_speed, o.approach_lateral,
      o.approach_along, o.duration, o.steps, o.trajectory);
  }
};

}  // namespace mg::system
