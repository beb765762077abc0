#pragma once
// Reading one input file (a spec or include, an arm model, a mesh, a recorded CSV, a learner
// model file) whole into memory, refusing what is not a plain file of sensible size: FIFOs,
// devices, sockets and directories are refused without opening them for a blocking read, and
// a file over its kind's size cap is refused before it is read. Every read of a user-named
// file in engine/ and runner/ goes through here (the path policy: sweeps/README.md and
// models/README.md, "Input files").
#include <cstdint>
#include <stdexcept>
#include <string>

namespace armfarm {

/// What an input file is; each kind has its own size cap.
enum class InputFileKind {
  json,           ///< sweep specs, includes, job configurations, tolerances, thesis results
  arm_model,      ///< URDF and DCG files
  mesh,           ///< Wavefront OBJ meshes
  table,          ///< numeric CSV files (recorded trajectories, training data)
  learner_model,  ///< LWPR and SSGPR model files
  any,            ///< a file read only to hash it: the largest of the caps above
};

/// The largest accepted size of each kind, bytes. The defaults are far above the files armfarm
/// ships (the largest is a 48 KB JSON) and below what a 24 GB machine parses comfortably;
/// sweeps/README.md ("Input files") gives the reasoning.
struct InputSizeCaps {
  std::uint64_t json = 16ull << 20;             ///< 16 MiB
  std::uint64_t arm_model = 16ull << 20;        ///< 16 MiB
  std::uint64_t mesh = 256ull << 20;            ///< 256 MiB: a 2-million-triangle OBJ
  std::uint64_t table = 1ull << 30;             ///< 1 GiB: 7 joints at 1 kHz for about 4 hours
  std::uint64_t learner_model = 2ull << 30;     ///< 2 GiB: LWPR with ~10^5 21-D receptive fields

  std::uint64_t cap(InputFileKind kind) const;
};

/// The word for a kind in messages ("mesh", "arm model", ...).
const char* describe_input_kind(InputFileKind kind);

/// An input file that is not a readable regular file under its cap. what() is one line
/// "PATH: problem"; it never quotes the file's content.
class InputFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The bytes of the regular file `path`. Throws InputFileError for a missing or unreadable
/// path, anything but a regular file (checked with stat before the open, which is non-blocking,
/// and again with fstat on the opened descriptor), or a file larger than caps.cap(kind)
/// (checked before reading and again while reading, in case it grows).
std::string read_input_file(const std::string& path, InputFileKind kind, const InputSizeCaps& caps = {});

/// read_input_file with its error rethrown as `Error` (ModelError, SpecError-like one-line types).
template <typename Error>
std::string read_input_file_as(const std::string& path, InputFileKind kind, const InputSizeCaps& caps = {}) {
  try {
    return read_input_file(path, kind, caps);
  } catch (const InputFileError& error) {
    throw Error(error.what());
  }
}

/// Where a file named inside another file that sits in `folder` (a DCG mesh f[...]) is: `folder`
/// joined with `written`, which must be relative and stay inside `folder` after lexical
/// normalisation (no leading '/', no '..' that climbs out). Throws InputFileError
/// "'WRITTEN' is an absolute path ..." without the folder (the caller names the file and line).
std::string resolve_confined_path(const std::string& folder, const std::string& written);

/// Throws InputFileError when `path` (as resolve_confined_path gave it, and existing) is, after
/// following every symbolic link, not inside the real folder of `folder`: a link in a model's
/// folder that points elsewhere (at /etc/shadow) is refused before the file is opened. `written`
/// is the name as the model wrote it, for the message. A missing file is left to the reader.
void check_real_path_inside(const std::string& folder, const std::string& path, const std::string& written);

}  // namespace armfarm
