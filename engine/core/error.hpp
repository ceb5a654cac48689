// The one exception type the library throws. Every error names what was wrong
// and where (file, line or byte offset, field), so a user can fix the input.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

namespace sarmap {

enum class ErrorCode {
  InvalidArgument,  // a caller passed a value outside what the API accepts
  Io,               // a file could not be opened, read, written or renamed
  Parse,            // a file's content does not follow its format
  Unsupported,      // a valid but unimplemented variant of a format
  InvalidData,      // well-formed input whose values are unusable (NaN pose, ...)
  OutOfRange,       // coordinates or sizes beyond what the map can represent
};

std::string_view to_string(ErrorCode code);

class Error : public std::runtime_error {
 public:
  Error(ErrorCode code, const std::string& message);

  ErrorCode code() const noexcept { return code_; }

 private:
  ErrorCode code_;
};

// Builds "file:line: message" (line omitted when 0) for parse errors.
std::string at_line(std::string_view file, std::size_t line, std::string_view message);
// Builds "file (byte offset N): message" for binary formats.
std::string at_offset(std::string_view file, std::size_t offset, std::string_view message);

}  // namespace sarmap
