#include "engine/pipeline/checkpoint.hpp"

#include <fstream>
#include <iterator>
#include <string_view>

#include "engine/core/error.hpp"
#include "engine/io/atomic_file.hpp"
#include "engine/io/sha256.hpp"

namespace sarmap::pipeline {
namespace {

constexpr std::string_view kMagic = "SARMAPCK";
constexpr std::size_t kDigestChars = 64;

// The file's bytes without the trailing digest, after checking it.
std::string read_verified(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(ErrorCode::Io, file.string() + ": cannot open the checkpoint");
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw Error(ErrorCode::Io, file.string() + ": cannot read the checkpoint");
  if (bytes.size() < kMagic.size() + kDigestChars || std::string_view(bytes).substr(0, kMagic.size()) != kMagic) {
    throw Error(ErrorCode::Parse, file.string() + ": not a sarmap checkpoint");
  }
  const std::string stored = bytes.substr(bytes.size() - kDigestChars);
  bytes.resize(bytes.size() - kDigestChars);
  if (sha256_hex(bytes) != stored) {
    throw Error(ErrorCode::Parse, file.string() + ": the checkpoint is damaged (its SHA-256 does not match)");
  }
  return bytes;
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
  const std::string bytes = read_verified(file);
  StateReader in(bytes, file.string());
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
