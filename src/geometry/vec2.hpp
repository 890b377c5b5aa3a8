#pragma once
// A plain 2D vector in metres (or any unit the caller keeps consistent).
#include <cmath>

namespace millwear {

struct Vec2 {
  double x = 0.0;
  double y = 0.0;
};

inline Vec2 operator+(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
inline Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
inline Vec2 operator-(Vec2 a) { return {-a.x, -a.y}; }
inline Vec2 operator*(double s, Vec2 a) { return {s * a.x, s * a.y}; }
inline Vec2 operator*(Vec2 a, double s) { return {s * a.x, s * a.y}; }
inline Vec2 operator/(Vec2 a, double s) { return {a.x / s, a.y / s}; }
inline Vec2& operator+=(Vec2& a, Vec2 b) { a.x += b.x; a.y += b.y; return a; }
inline Vec2& operator-=(Vec2& a, Vec2 b) { a.x -= b.x; a.y -= b.y; return a; }
inline bool operator==(Vec2 a, Vec2 b) { return a.x == b.x && a.y == b.y; }
inline double dot(Vec2 a, Vec2 b) { return a.x * b.x + a.y * b.y; }
inline double cross(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }
inline double length(Vec2 a) { return std::hypot(a.x, a.y); }
inline double length_sq(Vec2 a) { return a.x * a.x + a.y * a.y; }
inline Vec2 normalized(Vec2 a) { double l = length(a); return l > 0 ? a / l : Vec2{}; }
// Left perpendicular (rotate +90 deg).
inline Vec2 left_perp(Vec2 a) { return {-a.y, a.x}; }
inline Vec2 right_perp(Vec2 a) { return {a.y, -a.x}; }
inline Vec2 rotated(Vec2 a, double angle_rad) {
  double c = std::cos(angle_rad), s = std::sin(angle_rad);
  return {c * a.x - s * a.y, s * a.x + c * a.y};
}

}  // namespace millwear
