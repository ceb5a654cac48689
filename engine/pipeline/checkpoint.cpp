#include "engine/pipeline/checkpoint.hpp"

#include <cstdint>
#include <string_view>

#include "engine/core/error.hpp"
#include "engine/io/digested_file.hpp"

namespace sarmap::pipeline {
namespace {

constexpr std::string_view kCheckpointMagic = "SARMAPCK";

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
  write_digested_file(file, out.bytes());
}

CheckpointHeader load_checkpoint(const std::filesystem::path& file, const std::string& fingerprint, Mapper& mapper) {
  const FileBytes file_bytes = read_digested_file(file, kCheckpointMagic, "checkpoint");
  StateReader in(digested_body(file_bytes), file.string());
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
