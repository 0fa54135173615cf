// Maybe<T>: an optional number in the space of the number itself (a NaN or INT_MIN sentinel),
// for the per-segment cost terms: a country has tens of millions of segments, and
// std::optional<double> takes 16 bytes where a float with a NaN takes 4.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <type_traits>

namespace roadcross::preprocess {

template <typename T>
struct MaybeTraits;

template <>
struct MaybeTraits<double> {
  static constexpr double absent() noexcept { return std::numeric_limits<double>::quiet_NaN(); }
  static bool is_absent(double v) noexcept { return std::isnan(v); }
};

template <>
struct MaybeTraits<float> {
  static constexpr float absent() noexcept { return std::numeric_limits<float>::quiet_NaN(); }
  static bool is_absent(float v) noexcept { return std::isnan(v); }
};

template <>
struct MaybeTraits<std::int8_t> {
  static constexpr std::int8_t absent() noexcept { return std::numeric_limits<std::int8_t>::min(); }
  static bool is_absent(std::int8_t v) noexcept { return v == absent(); }
};

template <>
struct MaybeTraits<int> {
  static constexpr int absent() noexcept { return std::numeric_limits<int>::min(); }
  static bool is_absent(int v) noexcept { return v == absent(); }
};

/// Behaves like std::optional<T> for what the build needs (has_value, *, value_or, assignment
/// from a T, std::nullopt or a std::optional<T>). The sentinel itself cannot be stored: a NaN
/// double or INT_MIN assigned to it reads back as absent.
template <typename T>
class Maybe {
 public:
  constexpr Maybe() noexcept = default;
  constexpr Maybe(std::nullopt_t) noexcept {}
  /// From any number (a double stored in a float is rounded to the float's 7 digits).
  template <typename U>
  requires std::is_arithmetic_v<U>
  constexpr Maybe(U value) noexcept : value_(static_cast<T>(value)) {}
  /// Widening from a smaller Maybe of the same kind (a MaybeSmallInt reads as a MaybeInt).
  template <typename U>
  requires(std::is_integral_v<U> == std::is_integral_v<T> &&
           sizeof(U) < sizeof(T)) constexpr Maybe(Maybe<U> value) noexcept
      : value_(value ? static_cast<T>(*value) : MaybeTraits<T>::absent()) {}
  template <typename U>
  constexpr Maybe(const std::optional<U>& value) noexcept
      : value_(value ? static_cast<T>(*value) : MaybeTraits<T>::absent()) {}

  bool has_value() const noexcept { return !MaybeTraits<T>::is_absent(value_); }
  explicit operator bool() const noexcept { return has_value(); }
  T operator*() const noexcept { return value_; }
  T value_or(T fallback) const noexcept { return has_value() ? value_ : fallback; }
  std::optional<T> optional() const noexcept {
    return has_value() ? std::optional<T>(value_) : std::nullopt;
  }
  friend bool operator==(const Maybe& a, std::nullopt_t) noexcept { return !a.has_value(); }

 private:
  T value_ = MaybeTraits<T>::absent();
};

using MaybeDouble = Maybe<double>;
/// Metres, degrees, km/h at float precision (7 digits: below a millimetre for a 10 km value).
using MaybeFloat = Maybe<float>;
using MaybeInt = Maybe<int>;
/// A cost, level or rank that the code clamps to a small range (-127..127): 1 byte. A larger
/// value would wrap, so only fields whose computation bounds them use it.
using MaybeSmallInt = Maybe<std::int8_t>;

}  // namespace roadcross::preprocess
