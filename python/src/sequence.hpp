// A scan sequence held for Python: the ScanSource, the path it was opened
// from (for a run's manifest, Mapper.write(input=...)) and a lock, since
// frames are read without the GIL.
#pragma once

#include <memory>
#include <mutex>
#include <string>

#include "engine/io/scan_source.hpp"

namespace sarmap::python {

class Sequence {
 public:
  Sequence(std::string path, const ScanSequenceOptions& options);

  const std::string& path() const { return path_; }
  const ScanSource& source() const { return *source_; }
  bool next(Scan& scan);
  void rewind();
  // The next frame read is `frame` (past the end: none).
  void skip_to(std::size_t frame);

 private:
  std::string path_;
  std::unique_ptr<ScanSource> source_;
  std::mutex mutex_;
};

}  // namespace sarmap::python
