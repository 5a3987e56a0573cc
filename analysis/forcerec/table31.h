// 004 Table 3.1: the table dynamometer's transfer functions Hxx, Hyy, Hzz (004 eq. 3.1, 6th
// order, relative degree one) as measured after the last machining pass (seeds/004, lines
// 873-886; notes/004.md section 2 restates them identically). num = b1..b6, den = a1..a6 (monic
// denominator), units s^-i. The synthetic campaigns use them as the true dynamometer and the
// tests as the published reference.
#pragma once

#include <array>

namespace chatterlab {
namespace forcerec {

struct Table31Axis {
  char axis;         // 'x', 'y', 'z'
  const char* name;  // "Hxx", "Hyy", "Hzz"
  std::array<double, 6> num, den;
};

inline constexpr std::array<Table31Axis, 3> kTable31 = {{
    {'x',
     "Hxx",
     {3566, 8.364e7, 7.676e11, 1.432e16, 3.933e19, 6.0186e23},
     {3788, 2.563e8, 6.425e11, 2.164e16, 2.709e19, 6.019e23}},
    {'y',
     "Hyy",
     {2226, 5.652e7, 4.639e11, 9.460e15, 2.207e19, 3.377e23},
     {3308, 2.383e8, 5.580e11, 1.624e16, 1.934e19, 3.376e23}},
    {'z',
     "Hzz",
     {6150, 1.507e8, 1.425e12, 2.790e16, 5.788e19, 9.731e23},
     {2788, 3.308e8, 5.375e11, 3.324e16, 2.087e19, 9.319e23}},
}};

}  // namespace forcerec
}  // namespace chatterlab
