// Typed exceptions of the core. Real errors (bad input, impossible requests) are exceptions; algorithmic
// outcomes (SAFE / UNSAFE / UNDECIDED, an unbounded enclosure) are values, never exceptions.
#pragma once

#include <stdexcept>
#include <string>

namespace pkm_accuracy {

/// Base of every exception the core throws.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};

/// A caller supplied an invalid value. The message names the offending field, what was expected and what was
/// given, e.g. "sensor_error[3]: expected a finite value > 0, got -1".
class InvalidArgument : public Error {
 public:
  explicit InvalidArgument(const std::string& what) : Error(what) {}
};

/// A robot geometry that cannot be a PKM (coincident anchors, wrong number of legs, ...).
class InvalidGeometry : public InvalidArgument {
 public:
  explicit InvalidGeometry(const std::string& what) : InvalidArgument(what) {}
};

/// A point (non-interval) computation hit a singular matrix, e.g. the exact inverse Jacobian at a singular pose.
/// Interval methods never throw this: over a box containing a singularity they return an unbounded enclosure.
class SingularMatrix : public Error {
 public:
  explicit SingularMatrix(const std::string& what) : Error(what) {}
};

/// A defect of the library itself, not of its input: e.g. the verifier's self-check (VerifierOptions::self_check)
/// found a point whose error, evaluated in plain double, lies outside the bounds an enclosure certified for its box.
/// The message names what failed and where.
class InternalError : public Error {
 public:
  explicit InternalError(const std::string& what) : Error(what) {}
};

/// A file or document could not be read or has the wrong structure (the message names the file and the key).
class ParseError : public InvalidArgument {
 public:
  explicit ParseError(const std::string& what) : InvalidArgument(what) {}
};

}  // namespace pkm_accuracy
