#include "engine/pipeline/checkpoint.hpp"

#include <cstdint>
#include <limits>
#include <string_view>

#include "engine/core/error.hpp"
#include "engine/io/atomic_file.hpp"
#include "engine/io/file_bytes.hpp"
#include "engine/io/sha256.hpp"

namespace sarmap::pipeline {
namespace {

constexpr std::string_view kMagic = "SARMAPCK";
constexpr std::size_t kDigestChars = 64;

// The file's bytes, after checking the trailing digest. A checkpoint is no
// input from outside: it may be as large as the state it holds, so the input
// limits on file size do not apply.
FileBytes read_verified(const std::filesystem::path& file) {
  FileBytes file_bytes = read_file_bytes(file, std::numeric_limits<std::uint64_t>::max());
  const std::string_view bytes = file_bytes.view();
  if (bytes.size() < kMagic.size() + kDigestChars || bytes.substr(0, kMagic.size()) != kMagic) {
    throw Error(ErrorCode::Parse, file.string() + ": not a sarmap checkpoint");
  }
  const std::string_view stored = bytes.substr(bytes.size() - kDigestChars);
  if (sha256_hex(bytes.substr(0, bytes.size() - kDigestChars)) != stored) {
    throw Error(ErrorCode::Parse, file.string() + ": the checkpoint is damaged (its SHA-256 does not match)");
  }
  return file_bytes;
}

CheckpointHeader read_header(StateReader& in, const std::filesystem::path& file) {
  in.expect_tag("SARM");
  in.expect_tag("APCK");
  const auto version = in.get<std::uint32_t>();
  if (version != kCheckpointVersion) {
    throw Error(ErrorCode::Parse, file.string() + ": checkpoint version " + std::to_string(version) +
                                      ", this sarmap reads version " + std::to_string(kCheckpointVersion));
  }
  CheckpointHeader header;
  header.fingerprint = in.get_string();
  header.next_frame = in.get<std::uint64_t>();
  header.scans = in.get<std::uint64_t>();
  header.elapsed_s = in.get<double>();
  return header;
}

}  // namespace

void save_checkpoint(const std::filesystem::path& file, const CheckpointHeader& header, const Mapper& mapper) {
  StateWriter out;
  out.tag("SARM");
  out.tag("APCK");
  out.put(kCheckpointVersion);
  out.put_string(header.fingerprint);
  out.put(header.next_frame);
  out.put(header.scans);
  out.put(header.elapsed_s);
  mapper.save_state(out);
  AtomicFileWriter writer(file);
  writer.write(out.bytes());
  writer.write(sha256_hex(out.bytes()));
  writer.commit();
}

CheckpointHeader load_checkpoint(const std::filesystem::path& file, const std::string& fingerprint, Mapper& mapper) {
  const FileBytes file_bytes = read_verified(file);
  StateReader in(file_bytes.view().substr(0, file_bytes.size() - kDigestChars), file.string());
  CheckpointHeader header = read_header(in, file);
  if (header.fingerprint != fingerprint) {
    throw Error(ErrorCode::InvalidArgument,
                file.string() + ": the checkpoint is of a run with other settings or input (fingerprint " +
                    header.fingerprint.substr(0, 12) + "..., this run " + fingerprint.substr(0, 12) +
                    "...); run without --resume to start over");
  }
  mapper.load_state(in);
  in.expect_end();
  return header;
}

}  // namespace sarmap::pipeline
