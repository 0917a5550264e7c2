// Interval linear algebra for small square systems (n <= kMaxDof): rigorous products with point matrices and
// interval Gauss elimination. Failure to enclose (a pivot that contains zero) is a return value, not an exception.
#pragma once

#include "pkm_accuracy/core/Types.hpp"

namespace pkm_accuracy {
namespace enclosure {

/// Rigorous enclosure of C * A (C point, A interval).
IMat multiply(const DMat& c, const IMat& a);
/// Rigorous enclosure of A * C (A interval, C point).
IMat multiply(const IMat& a, const DMat& c);
/// Rigorous enclosure of C * A in midpoint-radius form: C mid(A) +- (|C| rad(A) + rounding-error bound), with
/// three double matrix products (vectorised) instead of interval arithmetic. The rounding-error bound is a priori
/// (gamma_n |C| |mid(A)|, valid in every rounding mode). At most ~1.5x wider than multiply() in the worst case,
/// practically equal for thin A; an order of magnitude cheaper.
IMat multiplyMidRad(const DMat& c, const IMat& a);
/// The same for A * C.
IMat multiplyMidRad(const IMat& a, const DMat& c);
/// Rigorous enclosure of A * B (both interval).
IMat multiply(const IMat& a, const IMat& b);

/// Encloses the solutions of A X = B for every point matrix in A (and every right-hand side in B) by interval
/// Gauss elimination, with partial pivoting on the largest mignitude when `pivoting` is set.
/// @return false (X unspecified) when a pivot contains zero, i.e. A may be singular or the method is too weak.
bool gaussSolve(IMat a, IMat b, IMat& x, bool pivoting);
/// Enclosure of { A^-1 : A in the interval matrix } (Gauss-Jordan with identity right-hand side).
bool gaussInverse(const IMat& a, IMat& inverse, bool pivoting);

/// The sign of det A certified for every point matrix in the (square) interval matrix A: +1 or -1, or 0 if it could
/// not be certified (A may contain a singular matrix, or the method is too weak). Interval Gauss elimination with
/// partial pivoting on the largest mignitude (det = the permutation's sign times the product of the pivots, each
/// enclosed for every member), and where a pivot contains zero, the same on C A with C an approximate inverse of
/// mid(A) (sign det A = sign det (C A) * sign det C, the latter on the point matrix C).
int determinantSign(const IMat& a);

/// Approximate inverse of a point matrix (double; any accuracy is fine where it is used as a preconditioner).
/// @return false if the matrix is numerically singular.
bool approximateInverse(const DMat& a, DMat& inverse);

/// Midpoints of an interval matrix.
DMat midpoint(const IMat& a);

}  // namespace enclosure
}  // namespace pkm_accuracy
