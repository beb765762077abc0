// The confined input reader: regular files only (no FIFO, device, directory, socket), each
// kind under its size cap, one-line errors that name the path and never quote the content.
#include "engine/io/input_file.hpp"
#include "engine/model/model_loading.hpp"
#include "engine/model/triangle_mesh.hpp"

#include <gtest/gtest.h>

#include "support/scratch_file.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

namespace armfarm {
namespace {

namespace fs = std::filesystem;

class InputFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test_support::make_scratch_folder("input_file");
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& bytes) {
    const fs::path path = dir_ / name;
    fs::create_directories(path.parent_path());
    std::ofstream(path, std::ios::binary) << bytes;
    return path.string();
  }

  // The InputFileError message of reading `path` as `kind`, or "(read)" when it reads.
  static std::string error_of(const std::string& path, InputFileKind kind, const InputSizeCaps& caps = {}) {
    try {
      read_input_file(path, kind, caps);
    } catch (const InputFileError& error) {
      return error.what();
    }
    return "(read)";
  }

  fs::path dir_;
};

TEST_F(InputFileTest, ReadsARegularFileByteForByte) {
  const std::string bytes = std::string("a,b\n1,2\r\n") + '\0' + "\xff tail";
  const std::string path = write("t.csv", bytes);
  EXPECT_EQ(read_input_file(path, InputFileKind::table), bytes);
  EXPECT_EQ(read_input_file(write("empty.json", ""), InputFileKind::json), "");
}

TEST_F(InputFileTest, FollowsASymlinkToARegularFile) {
  const std::string target = write("real.json", "{}");
  fs::create_symlink(target, dir_ / "link.json");
  EXPECT_EQ(read_input_file((dir_ / "link.json").string(), InputFileKind::json), "{}");
}

TEST_F(InputFileTest, RefusesAMissingFileNamingThePath) {
  const std::string path = (dir_ / "nope.urdf").string();
  EXPECT_EQ(error_of(path, InputFileKind::arm_model), path + ": no such file");
  EXPECT_EQ(error_of("", InputFileKind::json), "(empty path): no file named");
}

TEST_F(InputFileTest, RefusesADirectory) {
  EXPECT_EQ(error_of(dir_.string(), InputFileKind::json), dir_.string() + ": is a directory, not a regular file");
}

TEST_F(InputFileTest, RefusesDevZeroAndDevNullAtOnce) {
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(error_of("/dev/zero", InputFileKind::json), "/dev/zero: is a character device, not a regular file");
  EXPECT_EQ(error_of("/dev/null", InputFileKind::table), "/dev/null: is a character device, not a regular file");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
}

TEST_F(InputFileTest, RefusesAFifoWithoutWaitingForAWriter) {
  const std::string path = (dir_ / "pipe.json").string();
  ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0);
  // No writer ever opens the FIFO: a blocking open or read would hang here (ctest's timeout).
  EXPECT_EQ(error_of(path, InputFileKind::json), path + ": is a FIFO (named pipe), not a regular file");
}

TEST_F(InputFileTest, RefusesAFileOverItsKindsCapBeforeReadingIt) {
  InputSizeCaps caps;
  caps.mesh = 10;
  const std::string path = write("big.obj", std::string(11, 'v'));
  EXPECT_EQ(error_of(path, InputFileKind::mesh, caps), path + ": is 11 bytes, over the 10 bytes cap for mesh files");
  EXPECT_EQ(error_of(write("ok.obj", std::string(10, 'v')), InputFileKind::mesh, caps), "(read)");
  // Another kind keeps its own cap.
  EXPECT_EQ(error_of(path, InputFileKind::json, caps), "(read)");
}

TEST_F(InputFileTest, DefaultCapsAreMebibytesAndAnyIsTheLargest) {
  const InputSizeCaps caps;
  EXPECT_EQ(caps.cap(InputFileKind::json), 16u << 20);
  EXPECT_EQ(caps.cap(InputFileKind::any), caps.cap(InputFileKind::learner_model));
  for (InputFileKind kind : {InputFileKind::json, InputFileKind::arm_model, InputFileKind::mesh, InputFileKind::table,
                             InputFileKind::learner_model}) {
    EXPECT_LE(caps.cap(kind), caps.cap(InputFileKind::any));
  }
}

TEST_F(InputFileTest, UnreadableFileIsRefusedWithoutItsContent) {
  if (::geteuid() == 0) GTEST_SKIP() << "root reads files whatever their mode";
  const std::string path = write("secret.json", "{\"password\": \"hunter2\"}");
  fs::permissions(path, fs::perms::none);
  const std::string message = error_of(path, InputFileKind::json);
  EXPECT_EQ(message, path + ": permission denied");
}

TEST_F(InputFileTest, ErrorRethrownAsTheCallersType) {
  EXPECT_THROW(read_input_file_as<ModelError>("/dev/zero", InputFileKind::arm_model), ModelError);
}

TEST(ConfinedPath, JoinsRelativeNamesInsideTheFolder) {
  EXPECT_EQ(resolve_confined_path("/m", "obj/tip.obj"), "/m/obj/tip.obj");
  EXPECT_EQ(resolve_confined_path("/m/", "./obj/../obj/tip.obj"), "/m/obj/tip.obj");
  EXPECT_EQ(resolve_confined_path("", "tip.obj"), "tip.obj");
}

TEST(ConfinedPath, RefusesAbsoluteAndClimbingNames) {
  auto problem = [](const std::string& written) {
    try {
      resolve_confined_path("/m", written);
    } catch (const InputFileError& error) {
      return std::string(error.what());
    }
    return std::string("(accepted)");
  };
  EXPECT_EQ(problem("/etc/passwd"), "'/etc/passwd' is an absolute path; name files relative to the model file's folder");
  EXPECT_EQ(problem("/dev/zero"), "'/dev/zero' is an absolute path; name files relative to the model file's folder");
  EXPECT_NE(problem("../secret.obj").find("leaves the model file's folder"), std::string::npos);
  EXPECT_NE(problem("obj/../../x.obj").find("leaves the model file's folder"), std::string::npos);
  EXPECT_EQ(problem(""), "no file named");
}

// A DCG body whose mesh is f[NAME], in a fresh folder; the ModelError of loading it.
class DcgMeshPath : public InputFileTest {
 protected:
  std::string load_error(const std::string& mesh) {
    const std::string path = write("arm.dcg", "<DCGraph>\nB ground <t(0 0 0)> o(1) s(1 1 0.1) fix;\nB arm <> f[" + mesh +
                                                  "] o(3) w(1);\nJ ground-arm <t(0 0 0.1)>;\n</DCGraph>\n");
    try {
      load_arm_model(path);
    } catch (const ModelError& error) {
      return error.what();
    }
    return "(loaded)";
  }
};

TEST_F(DcgMeshPath, AbsoluteMeshPathsAreRefusedWithoutReadingThem) {
  const auto start = std::chrono::steady_clock::now();
  const std::string zero = load_error("/dev/zero");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
  EXPECT_NE(zero.find("arm.dcg:3: body 'arm': f[...]: '/dev/zero' is an absolute path"), std::string::npos) << zero;
  const std::string passwd = load_error("/etc/passwd");
  EXPECT_NE(passwd.find("arm.dcg:3: body 'arm': f[...]: '/etc/passwd' is an absolute path"), std::string::npos) << passwd;
  EXPECT_EQ(passwd.find("root"), std::string::npos) << passwd;
}

TEST_F(DcgMeshPath, MeshPathsClimbingOutOfTheModelFolderAreRefused) {
  const std::string up = load_error("../outside.obj");
  EXPECT_NE(up.find("arm.dcg:3: body 'arm': f[...]: '../outside.obj' leaves the model file's folder"), std::string::npos) << up;
}

TEST_F(DcgMeshPath, AFifoOrFolderMeshIsRefusedWithTheDcgLine) {
  ASSERT_EQ(::mkfifo((dir_ / "pipe.obj").c_str(), 0600), 0);
  const std::string fifo = load_error("pipe.obj");
  EXPECT_NE(fifo.find("arm.dcg:3: body 'arm': "), std::string::npos) << fifo;
  EXPECT_NE(fifo.find("pipe.obj: is a FIFO (named pipe), not a regular file"), std::string::npos) << fifo;
  fs::create_directories(dir_ / "obj");
  const std::string folder = load_error("obj");
  EXPECT_NE(folder.find("obj: is a directory, not a regular file"), std::string::npos) << folder;
}

TEST_F(InputFileTest, MeshReaderRefusesDevZeroAndAFolder) {
  try {
    load_obj_mesh("/dev/zero");
    FAIL() << "read /dev/zero";
  } catch (const ModelError& error) {
    EXPECT_STREQ(error.what(), "/dev/zero: is a character device, not a regular file");
  }
}

}  // namespace
}  // namespace armfarm
