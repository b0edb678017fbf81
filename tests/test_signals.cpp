// SIGINT and SIGTERM in the commands: every output of a command appears together or not at all, and
// no temporary file survives (libstm/core/atomic_file.h: the registry, OutputCommit, ScratchFile).
// Each command runs as a process with its own TMPDIR and SDM_TEST_PAUSE_AFTER_WRITE, the hook that
// makes it stop and say so at one stage; the test sends the signal there and waits for the end.
#include "libsdm/map/sdm_exr.h"
#include "libstm/core/atomic_file.h"
#include "libstm/core/image.h"
#include "test_util.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

namespace fs = std::filesystem;

namespace {

const std::string kSpot = std::string(SDM_EXAMPLES) + "/spot/spot_triangulated.obj";
const std::string kSpotTexture = std::string(SDM_EXAMPLES) + "/spot/spot_texture.png";

struct Ending {
  bool paused = false;  // the command reached the stage
  int signal = 0;       // the signal that ended it (0: it exited)
  int exit_code = -1;
  std::string stderr_text;
};

// Runs `sdm ARGS` with TMPDIR=`tmpdir` and the pause hook at `stage`; once the command says it
// paused there, sends it `sig` and waits for its end.
Ending interrupt_at(const std::vector<std::string>& args, const std::string& stage, int sig, const fs::path& tmpdir) {
  int err[2];
  REQUIRE(pipe(err) == 0);
  const pid_t pid = fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    setenv("TMPDIR", tmpdir.c_str(), 1);
    setenv("SDM_TEST_PAUSE_AFTER_WRITE", stage.c_str(), 1);
    for (int s : {SIGINT, SIGTERM}) signal(s, SIG_DFL);  // as from a terminal, whatever the test runner ignores
    const int null = open("/dev/null", O_WRONLY);
    dup2(null, 1);
    dup2(err[1], 2);
    close(err[0]);
    std::vector<char*> argv = {const_cast<char*>(SDM_BINARY)};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(SDM_BINARY, argv.data());
    _exit(127);
  }
  close(err[1]);
  Ending e;
  char buf[4096];
  ssize_t n;
  while (!e.paused && (n = read(err[0], buf, sizeof buf)) > 0) {
    e.stderr_text.append(buf, size_t(n));
    if (e.stderr_text.find("sdm: test pause after") != std::string::npos) {
      e.paused = true;
      kill(pid, sig);
    }
  }
  while ((n = read(err[0], buf, sizeof buf)) > 0) e.stderr_text.append(buf, size_t(n));
  close(err[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  if (WIFSIGNALED(status)) e.signal = WTERMSIG(status);
  if (WIFEXITED(status)) e.exit_code = WEXITSTATUS(status);
  return e;
}

// The files left in `dir` (recursively), as names relative to it.
std::vector<std::string> files_in(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& f : fs::recursive_directory_iterator(dir))
    if (!f.is_directory()) names.push_back(fs::relative(f.path(), dir).string());
  return names;
}

// The bytes on disk at `path`.
std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

struct Folders {
  test_util::TempDir dir;
  fs::path out = dir.path / "out", tmp = dir.path / "tmp";
  Folders() {
    fs::create_directories(out);
    fs::create_directories(tmp);
  }
};

}  // namespace

TEST_CASE("roundtrip: a signal while its map is read back leaves no sdm-roundtrip file and no output", "[signals]") {
  for (int sig : {SIGINT, SIGTERM}) {
    Folders f;
    const Ending e = interrupt_at({"roundtrip", kSpot, "--size", "128", "--samples", "1000", "-o", (f.out / "back.obj").string()},
                                  "sdm-roundtrip-", sig, f.tmp);
    INFO(strsignal(sig) << ": " << e.stderr_text);
    CHECK(e.paused);
    CHECK(e.signal == sig);  // it died of the signal, as without the handler
    CHECK(files_in(f.tmp).empty());
    CHECK(files_in(f.out).empty());
  }
}

TEST_CASE("encode --png: a signal after the map is written leaves neither file; one during the commit leaves both", "[signals]") {
  const std::vector<std::string> names = {"spot.exr", "spot.png"};
  for (int sig : {SIGINT, SIGTERM}) {
    Folders f;
    const std::vector<std::string> args = {"encode", kSpot, "--size", "128", "-o", (f.out / names[0]).string(), "--png",
                                           (f.out / names[1]).string()};
    Ending e = interrupt_at(args, "spot.exr", sig, f.tmp);
    INFO(strsignal(sig) << ": " << e.stderr_text);
    CHECK(e.paused);
    CHECK(e.signal == sig);
    CHECK(files_in(f.out).empty());
    // The signal arrives once the map is renamed and the picture not yet: it waits for the commit to
    // end, then ends the command; both files are whole.
    e = interrupt_at(args, "commit", sig, f.tmp);
    INFO(e.stderr_text);
    CHECK(e.paused);
    CHECK(e.signal == sig);
    std::vector<std::string> left = files_in(f.out);
    std::sort(left.begin(), left.end());
    CHECK(left == names);
    CHECK(sdm::read_sdm_exr((f.out / names[0]).string()).width == 128);
    CHECK(sdm::read_png((f.out / names[1]).string()).width == 128);
    CHECK(files_in(f.tmp).empty());
  }
}

TEST_CASE("transfer: a signal after some outputs are written leaves none of them", "[signals]") {
  Folders f;
  const std::vector<std::string> args = {"transfer", "--source", kSpot, "--texture", kSpotTexture, "--target", kSpot, "--size", "256",
                                         "-o", (f.out / "t.obj").string(), "--correspondence", (f.out / "c.txt").string()};
  // The correspondence and the atlas are written, the preview and the mesh not yet.
  const Ending e = interrupt_at(args, "t_atlas.png", SIGTERM, f.tmp);
  INFO(e.stderr_text);
  CHECK(e.paused);
  CHECK(e.signal == SIGTERM);
  CHECK(files_in(f.out).empty());
  CHECK(files_in(f.tmp).empty());
}

TEST_CASE("An OutputCommit renames every output at once; destroyed uncommitted, it leaves the targets as they were", "[signals]") {
  test_util::TempDir dir;
  const std::string a = dir / "a.txt", b = dir / "b.txt";
  test_util::write_file(a, "old a");
  {
    sdm::OutputCommit commit;
    sdm::write_text_file(a, "new a");
    sdm::write_text_file(b, "new b");
    CHECK(file_bytes(a) == "old a");  // still the old one on disk: nothing renamed before the commit
    CHECK_FALSE(fs::exists(b));
    CHECK(sdm::read_text_file(b) == "new b");  // the command itself reads what it wrote (a glTF embedding its atlas)
    CHECK(files_in(dir.path).size() == 3);  // a and the two temporaries
  }
  CHECK(files_in(dir.path) == std::vector<std::string>{"a.txt"});
  CHECK(sdm::read_text_file(a) == "old a");
  {
    sdm::OutputCommit commit;
    sdm::write_text_file(a, "new a");
    sdm::write_text_file(b, "first b");
    sdm::write_text_file(b, "new b");  // the same output twice: the last one counts
    // A scratch file is written at once, also while a commit is open, and removed with its object.
    {
      const sdm::ScratchFile scratch(dir / "scratch.txt");
      sdm::write_text_file(scratch.path(), "scratch");
      CHECK(sdm::read_text_file(scratch.path()) == "scratch");
    }
    CHECK_FALSE(fs::exists(dir / "scratch.txt"));
    CHECK_THROWS_AS(sdm::OutputCommit(), std::logic_error);  // one at a time
    commit.commit();
  }
  CHECK(sdm::read_text_file(a) == "new a");
  CHECK(sdm::read_text_file(b) == "new b");
  CHECK(files_in(dir.path).size() == 2);
  // Without a commit open, a write is renamed at once, as before.
  sdm::write_text_file(b, "at once");
  CHECK(sdm::read_text_file(b) == "at once");
}
