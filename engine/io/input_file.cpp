#include "engine/io/input_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>

namespace armfarm {
namespace {

// What a stat mode is, for "PATH: is a FIFO, not a regular file".
const char* describe_file_type(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a plain file";
}

std::string describe_size(std::uint64_t bytes) {
  if (bytes >= (1ull << 20) && bytes % (1ull << 20) == 0) return std::to_string(bytes >> 20) + " MiB";
  return std::to_string(bytes) + " bytes";
}

[[noreturn]] void fail(const std::string& path, const std::string& what) { throw InputFileError(path + ": " + what); }

[[noreturn]] void fail_errno(const std::string& path, int error) {
  if (error == ENOENT) fail(path, "no such file");
  if (error == ENOTDIR) fail(path, "no such file (a folder on the way is a file)");
  if (error == EACCES) fail(path, "permission denied");
  fail(path, std::string("cannot read the file: ") + std::strerror(error));
}

[[noreturn]] void fail_size(const std::string& path, std::uint64_t size, InputFileKind kind, std::uint64_t cap) {
  fail(path, "is " + std::to_string(size) + " bytes, over the " + describe_size(cap) + " cap for " +
                 describe_input_kind(kind) + " files");
}

// Closes a descriptor on every way out.
struct Descriptor {
  int fd;
  ~Descriptor() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

std::uint64_t InputSizeCaps::cap(InputFileKind kind) const {
  switch (kind) {
    case InputFileKind::json: return json;
    case InputFileKind::arm_model: return arm_model;
    case InputFileKind::mesh: return mesh;
    case InputFileKind::table: return table;
    case InputFileKind::learner_model: return learner_model;
    case InputFileKind::any: return std::max({json, arm_model, mesh, table, learner_model});
  }
  return 0;
}

const char* describe_input_kind(InputFileKind kind) {
  switch (kind) {
    case InputFileKind::json: return "JSON";
    case InputFileKind::arm_model: return "arm model";
    case InputFileKind::mesh: return "mesh";
    case InputFileKind::table: return "CSV";
    case InputFileKind::learner_model: return "learner model";
    case InputFileKind::any: return "input";
  }
  return "input";
}

std::string read_input_file(const std::string& path, InputFileKind kind, const InputSizeCaps& caps) {
  if (path.empty()) throw InputFileError("(empty path): no file named");
  const std::uint64_t cap = caps.cap(kind);
  // stat first: a FIFO or a device is refused without being opened at all.
  struct stat before {};
  if (::stat(path.c_str(), &before) != 0) fail_errno(path, errno);
  if (!S_ISREG(before.st_mode)) fail(path, std::string("is ") + describe_file_type(before.st_mode) + ", not a regular file");
  if (static_cast<std::uint64_t>(before.st_size) > cap) fail_size(path, before.st_size, kind, cap);
  // O_NONBLOCK: should the path be swapped for a FIFO between stat and open, open does not wait
  // for a writer; fstat then sees what was really opened.
  Descriptor file{::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY)};
  if (file.fd < 0) fail_errno(path, errno);
  struct stat opened {};
  if (::fstat(file.fd, &opened) != 0) fail_errno(path, errno);
  if (!S_ISREG(opened.st_mode)) fail(path, std::string("is ") + describe_file_type(opened.st_mode) + ", not a regular file");
  if (static_cast<std::uint64_t>(opened.st_size) > cap) fail_size(path, opened.st_size, kind, cap);

  std::string bytes;
  bytes.resize(static_cast<std::size_t>(opened.st_size));
  std::size_t used = 0;
  for (;;) {
    if (used == bytes.size()) {
      // The file may have grown since fstat: read on in steps, never past cap + 1 bytes.
      if (used > cap) fail_size(path, used, kind, cap);
      bytes.resize(static_cast<std::size_t>(std::min<std::uint64_t>(cap + 1, used + 65536)));
    }
    const ssize_t got = ::read(file.fd, &bytes[used], bytes.size() - used);
    if (got < 0) {
      if (errno == EINTR) continue;
      fail_errno(path, errno);
    }
    if (got == 0) break;
    used += static_cast<std::size_t>(got);
  }
  if (used > cap) fail_size(path, used, kind, cap);
  bytes.resize(used);
  return bytes;
}

std::string resolve_confined_path(const std::string& folder, const std::string& written) {
  if (written.empty()) throw InputFileError("no file named");
  if (written.find('\0') != std::string::npos) throw InputFileError("the file name holds a NUL byte");
  const std::filesystem::path name(written);
  if (name.is_absolute()) {
    throw InputFileError("'" + written + "' is an absolute path; name files relative to the model file's folder");
  }
  const std::filesystem::path normal = name.lexically_normal();
  if (normal.empty() || *normal.begin() == "..") {
    throw InputFileError("'" + written + "' leaves the model file's folder; files a model names must lie inside it");
  }
  return (std::filesystem::path(folder.empty() ? "." : folder) / normal).lexically_normal().string();
}

void check_real_path_inside(const std::string& folder, const std::string& path, const std::string& written) {
  std::error_code error;
  const std::filesystem::path real = std::filesystem::canonical(path, error);
  if (error) return;  // missing or unreadable: read_input_file says which
  const std::filesystem::path real_folder = std::filesystem::canonical(folder.empty() ? "." : folder, error);
  if (error) return;
  // Inside: real_folder is a prefix of real, element by element (so /m2/x is not inside /m).
  auto file_part = real.begin();
  for (auto folder_part = real_folder.begin(); folder_part != real_folder.end(); ++folder_part, ++file_part) {
    if (file_part == real.end() || *file_part != *folder_part) {
      throw InputFileError("'" + written + "' is a symbolic link (or passes through one) to a file outside the model file's "
                           "folder; files a model names must lie inside it");
    }
  }
}

}  // namespace armfarm
