#pragma once
/// \file error.h
/// The one exception type of the project. Every stage throws `gridshell::Error` for bad input
/// (a file, an option, a model that cannot be analysed); the command-line front end turns it
/// into `gridshell: error: <subject>: <what>` and exit status 2.

#include <stdexcept>
#include <string>

namespace gridshell {

class Error : public std::runtime_error {
 public:
  /// \param subject the file or option at fault (may be empty)
  /// \param what    what is wrong, one line, no trailing period
  Error(std::string subject, const std::string& what)
      : std::runtime_error(what), subject_(std::move(subject)) {}

  const std::string& subject() const { return subject_; }

  /// "subject: what" or just "what".
  std::string message() const {
    return subject_.empty() ? std::string(what()) : subject_ + ": " + what();
  }

 private:
  std::string subject_;
};

}  // namespace gridshell
