// Vec2 / Point: the planar value type used everywhere in fairspline.
#pragma once

#include <algorithm>
#include <cmath>

namespace fairspline {

/// A planar vector (or point). Plain aggregate: {x, y}.
struct Vec2 {
  double x = 0.0;
  double y = 0.0;

  constexpr Vec2& operator+=(Vec2 o) {
    x += o.x;
    y += o.y;
    return *this;
  }
  constexpr Vec2& operator-=(Vec2 o) {
    x -= o.x;
    y -= o.y;
    return *this;
  }
  constexpr Vec2& operator*=(double s) {
    x *= s;
    y *= s;
    return *this;
  }
  friend constexpr bool operator==(Vec2, Vec2) = default;
};

/// Points and vectors share one type; the alias documents intent.
using Point = Vec2;

constexpr Vec2 operator+(Vec2 a, Vec2 b) {
  return {a.x + b.x, a.y + b.y};
}
constexpr Vec2 operator-(Vec2 a, Vec2 b) {
  return {a.x - b.x, a.y - b.y};
}
constexpr Vec2 operator-(Vec2 a) {
  return {-a.x, -a.y};
}
constexpr Vec2 operator*(double s, Vec2 a) {
  return {s * a.x, s * a.y};
}
constexpr Vec2 operator*(Vec2 a, double s) {
  return {s * a.x, s * a.y};
}
constexpr Vec2 operator/(Vec2 a, double s) {
  return {a.x / s, a.y / s};
}

/// Dot product a·b.
constexpr double dot(Vec2 a, Vec2 b) {
  return a.x * b.x + a.y * b.y;
}
/// 2-D cross product (z-component of a×b): positive when b is counter-clockwise of a.
constexpr double cross(Vec2 a, Vec2 b) {
  return a.x * b.y - a.y * b.x;
}
/// Squared Euclidean norm.
constexpr double norm2(Vec2 a) {
  return dot(a, a);
}
/// Euclidean norm, overflow-safe.
inline double norm(Vec2 a) {
  return std::hypot(a.x, a.y);
}
/// Distance between two points.
inline double distance(Point a, Point b) {
  return norm(b - a);
}
/// a rotated by +90 degrees.
constexpr Vec2 perp(Vec2 a) {
  return {-a.y, a.x};
}
/// Unit vector in the direction of a; a must be non-zero and finite. Divides by the largest
/// component first, so denormal and huge vectors give a unit vector too (a / norm(a) of
/// (5e-324, 5e-324) is (1, 1): the norm rounds to a denormal).
inline Vec2 normalized(Vec2 a) {
  const Vec2 b = a / std::max(std::abs(a.x), std::abs(a.y));
  return b / norm(b);
}
/// Polar angle of a in (-pi, pi].
inline double angle(Vec2 a) {
  return std::atan2(a.y, a.x);
}
/// Signed angle from a to b in (-pi, pi]: positive when turning counter-clockwise.
inline double signed_angle(Vec2 a, Vec2 b) {
  const Vec2 u = normalized(a), v = normalized(b);  // no overflow of the products near 1e308
  return std::atan2(cross(u, v), dot(u, v));
}
/// Unit vector at polar angle phi.
inline Vec2 from_angle(double phi) {
  return {std::cos(phi), std::sin(phi)};
}
/// a rotated counter-clockwise by phi.
inline Vec2 rotate(Vec2 a, double phi) {
  const double c = std::cos(phi), s = std::sin(phi);
  return {c * a.x - s * a.y, s * a.x + c * a.y};
}
/// Linear interpolation (1-u)a + u b.
constexpr Point lerp(Point a, Point b, double u) {
  return a + u * (b - a);
}
/// True when both coordinates are finite.
inline bool is_finite(Vec2 a) {
  return std::isfinite(a.x) && std::isfinite(a.y);
}

}  // namespace fairspline
