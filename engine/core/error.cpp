#include "engine/core/error.hpp"

namespace sarmap {

std::string_view to_string(ErrorCode code) {
  switch (code) {
    case ErrorCode::InvalidArgument: return "invalid argument";
    case ErrorCode::Io: return "I/O error";
    case ErrorCode::Parse: return "parse error";
    case ErrorCode::Unsupported: return "unsupported";
    case ErrorCode::InvalidData: return "invalid data";
    case ErrorCode::OutOfRange: return "out of range";
  }
  return "error";
}

Error::Error(ErrorCode code, const std::string& message)
    : std::runtime_error(message), code_(code) {}

std::string at_line(std::string_view file, std::size_t line, std::string_view message) {
  std::string out(file);
  if (line > 0) out += ":" + std::to_string(line);
  out += ": ";
  out += message;
  return out;
}

std::string at_offset(std::string_view file, std::size_t offset, std::string_view message) {
  std::string out(file);
  out += " (byte offset " + std::to_string(offset) + "): ";
  out += message;
  return out;
}

}  // namespace sarmap
