// sqrt, 1 / x, sin and cos of a first-order form F (interval::AffineForm, interval::SegmentAffineForm): the Taylor
// form at the centre, f(c) + f'(c) (x - c), with f(c) and f'(c) enclosed at the centre point and f'' over the form's
// range (F::taylor bounds the remainder; so libm's rounding is covered). NaN / inf for sqrt or 1 / x of ranges
// reaching 0: callers check finite().
#pragma once

#include "pkm_accuracy/core/interval/Functions.hpp"
#include "pkm_accuracy/core/interval/Interval.hpp"

namespace pkm_accuracy {
namespace interval {

template <typename F>
F taylorSqrt(const F& x) {
  const Interval c(x.centre()), range = x.toInterval();
  const Interval s = sqrt(c);
  // (sqrt)' = 1 / (2 sqrt), (sqrt)'' = -1 / (4 x sqrt(x)).
  return F::taylor(x, s, Interval(1.0) / (Interval(2.0) * s), -(Interval(1.0) / (Interval(4.0) * range * sqrt(range))));
}
template <typename F>
F taylorReciprocal(const F& x) {
  const Interval c(x.centre()), range = x.toInterval();
  const Interval inv = Interval(1.0) / c;
  return F::taylor(x, inv, -(inv * inv), Interval(2.0) / (range * range * range));
}
template <typename F>
F taylorSin(const F& x) {
  return F::taylor(x, sinPoint(x.centre()), cosPoint(x.centre()), -sin(x.toInterval()));
}
template <typename F>
F taylorCos(const F& x) {
  return F::taylor(x, cosPoint(x.centre()), -sinPoint(x.centre()), -cos(x.toInterval()));
}

}  // namespace interval
}  // namespace pkm_accuracy
