#pragma once
/// @file error.h
/// The one error type for bad input. It names the file and the element at fault; every main()
/// prints it as one line on stderr and exits with kExitBadInput.
#include <stdexcept>
#include <string>

namespace firstshot {

inline constexpr int kExitBadInput = 2;

class InputError : public std::runtime_error {
 public:
  /// @param file    the input file at fault (may be empty for command-line values)
  /// @param element where in the file: a JSON path such as "shapes[3].material", "line 4, column 7", or a section name
  /// @param message what is wrong, in plain words
  InputError(std::string file, std::string element, const std::string& message)
      : std::runtime_error(compose(file, element, message)), file_(std::move(file)), element_(std::move(element)) {}
  const std::string& file() const { return file_; }
  const std::string& element() const { return element_; }

 private:
  static std::string compose(const std::string& f, const std::string& e, const std::string& m) {
    std::string s = f.empty() ? std::string() : f + ": ";
    if (!e.empty()) s += e + ": ";
    return s + m;
  }
  std::string file_, element_;
};

}  // namespace firstshot
