#pragma once
/// One error policy for the whole project (see README "Errors").
///
/// Library code throws one of these at API and file boundaries; messages name the quantity and
/// say what was expected and what was found. The CLI turns any `mg::Error` into a one-line
/// message and a non-zero exit code. Real-time code (the 500 Hz tick) never throws: it reports
/// status values instead.
#include <stdexcept>
#include <string>

namespace mg {

/// Base of every error this project throws on purpose.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The user gave something we cannot use: a bad number, an unknown name, a malformed file.
class InputError : public Error {
 public:
  using Error::Error;
};

/// A file could not be read or written.
class IoError : public Error {
 public:
  using Error::Error;
};

/// An algorithm could not deliver (e.g. a fit that violates its constraints).
class NumericalError : public Error {
 public:
  using Error::Error;
};

}  // namespace mg
