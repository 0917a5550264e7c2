// Rotations in long double for the tests' independent oracles (frame compositions): R = Rz(yaw) Ry(pitch) Rx(roll)
// and products, about 3 decimal digits more accurate than the double code under test.
#pragma once

#include <array>
#include <cmath>

namespace pkm_accuracy {
namespace test {

using Mat3L = std::array<std::array<long double, 3>, 3>;

inline Mat3L product(const Mat3L& a, const Mat3L& b) {
  Mat3L c{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) c[i][j] += a[i][k] * b[k][j];
  return c;
}

/// The rotation R = Rz(yaw) Ry(pitch) Rx(roll) in long double.
inline Mat3L rpy(long double r, long double p, long double y) {
  const Mat3L rx = {{{1, 0, 0}, {0, std::cos(r), -std::sin(r)}, {0, std::sin(r), std::cos(r)}}};
  const Mat3L ry = {{{std::cos(p), 0, std::sin(p)}, {0, 1, 0}, {-std::sin(p), 0, std::cos(p)}}};
  const Mat3L rz = {{{std::cos(y), -std::sin(y), 0}, {std::sin(y), std::cos(y), 0}, {0, 0, 1}}};
  return product(rz, product(ry, rx));
}

}  // namespace test
}  // namespace pkm_accuracy
