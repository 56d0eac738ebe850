// pbrtrun-mpi under mpirun on this machine (label mpi): the image of one process, dynamic
// tiles with a slow rank, a broadcast archive, a damaged archive on one rank, and a rank
// killed mid-render whose job --resume finishes.
#include <signal.h>

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>

#include "pbrt/command_runner.h"
#include "runtime/film/render_state.h"
#include "test_support.h"

namespace testing_support {
namespace {

namespace fs = std::filesystem;

const std::string kDefaultScene = std::string(PBRTC_SOURCE_DIR) + "/tools/default-scene/scene.pbrt";
// As root Open MPI needs --allow-run-as-root; this machine has 2 cores, so 3 ranks need
// --oversubscribe.
const std::string kMpirun = "mpirun --allow-run-as-root --oversubscribe";

std::string compiled(const std::string& name) {
  const std::string dir = scratch_dir("mpi_" + name);
  const Outcome c = run_in(dir, kBin + "/pbrtc -q '" + kDefaultScene + "' -o scene.pbrta", "pbrtc");
  EXPECT_EQ(c.status, 0) << c.err;
  return dir;
}

std::string mpi(int ranks, const std::string& args) {
  return kMpirun + " -np " + std::to_string(ranks) + " " + kBin + "/pbrtrun-mpi " + args;
}

bool same_file(const std::string& a, const std::string& b) {
  const std::string x = read_file(a);
  return !x.empty() && x == read_file(b);
}

// 1, 2 and 3 ranks give the single process's image, bit for bit (tiles merge in order).
TEST(Mpi, AnyRankCountGivesTheImageOfOneProcess) {
  const std::string dir = compiled("ranks");
  const std::string base = " scene.pbrta -q --resdiv 4 --spp 32 --nthreads 1";
  const std::string common = base + " --seed 5";
  ASSERT_EQ(run_in(dir, kBin + "/pbrtrun" + common + " -o one.exr", "one").status, 0);
  for (int n : {1, 2, 3}) {
    const std::string out = "mpi" + std::to_string(n) + ".exr";
    const Outcome r = run_in(dir, mpi(n, common + " -o " + out), "mpi" + std::to_string(n));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(same_file(dir + "/one.exr", dir + "/" + out)) << n << " ranks";
  }
  // A different seed is a different image: the comparison can fail.
  ASSERT_EQ(run_in(dir, kBin + "/pbrtrun" + base + " --seed 6 -o six.exr", "six").status, 0);
  EXPECT_FALSE(same_file(dir + "/one.exr", dir + "/six.exr"));
}

// One rank ten times slower: the others take its share, and the image is unchanged.
TEST(Mpi, ASlowRankStillFinishesWithTheSameImage) {
  const std::string dir = compiled("slow");
  const std::string common = " scene.pbrta -q --resdiv 4 --spp 16 --nthreads 1";
  ASSERT_EQ(run_in(dir, kBin + "/pbrtrun" + common + " -o one.exr", "one").status, 0);
  const Outcome r =
      run_in(dir, mpi(3, common + " -o slow.exr --slow-rank 2 --slow-tile-seconds 0.05"), "slow");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(same_file(dir + "/one.exr", dir + "/slow.exr"));
}

// --broadcast-archive: only rank 0 can read the archive ("{rank}" names one per rank).
TEST(Mpi, BroadcastArchiveServesRanksWithoutTheFile) {
  const std::string dir = compiled("broadcast");
  fs::rename(dir + "/scene.pbrta", dir + "/scene0.pbrta");
  const std::string common = " -q --resdiv 4 --spp 16 --nthreads 1";
  const Outcome without = run_in(dir, mpi(3, "'scene{rank}.pbrta'" + common + " -o x.exr"), "no");
  EXPECT_NE(without.status, 0);
  EXPECT_NE(without.err.find("rank 1: error"), std::string::npos) << without.err;
  const Outcome with =
      run_in(dir, mpi(3, "'scene{rank}.pbrta' --broadcast-archive" + common + " -o b.exr"), "with");
  ASSERT_EQ(with.status, 0) << with.err;
  ASSERT_EQ(run_in(dir, kBin + "/pbrtrun scene0.pbrta" + common + " -o one.exr", "one").status, 0);
  EXPECT_TRUE(same_file(dir + "/one.exr", dir + "/b.exr"));
}

// A damaged archive on one rank: that rank says so, the job exits non-zero, no image.
TEST(Mpi, ADamagedArchiveOnOneRankIsReportedByIt) {
  const std::string dir = compiled("damaged");
  std::string bytes = read_file(dir + "/scene.pbrta");
  for (int r : {0, 1, 2}) {
    std::string copy = bytes;
    if (r == 2) copy[copy.size() / 2] ^= 0x55;
    write_file(dir + "/scene" + std::to_string(r) + ".pbrta", copy);
  }
  const Outcome r = run_in(dir, mpi(3, "'scene{rank}.pbrta' -q --resdiv 4 --spp 4 -o d.exr"));
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("rank 2: error: scene2.pbrta"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("rank 1: error"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/d.exr"));
}

// Integrators that do not render in passes of tiles are refused before any rendering.
TEST(Mpi, SppmAndMltAreRefused) {
  const std::string dir = scratch_dir("mpi_refused");
  for (const char* integrator : {"sppm", "mlt"}) {
    write_file(dir + "/s.pbrt", std::string("LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\n"
                                            "Film \"image\" \"integer xresolution\" 8 "
                                            "\"integer yresolution\" 8\nIntegrator \"") +
                                    integrator +
                                    "\"\nWorldBegin\nLightSource \"point\"\n"
                                    "Shape \"sphere\"\nWorldEnd\n");
    ASSERT_EQ(run_in(dir, kBin + "/pbrtc -q s.pbrt -o s.pbrta", "c").status, 0);
    const Outcome r = run_in(dir, mpi(2, "s.pbrta -q -o s.exr"), integrator);
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(
        r.err.find(std::string("not supported yet: the ") + integrator + " integrator under MPI"),
        std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(dir + "/s.exr"));
  }
}

// The rank of a process, from the environment Open MPI gives it; -1 if not one.
int rank_of(const std::string& pid) {
  const std::string env = read_file("/proc/" + pid + "/environ");
  const std::string key = std::string("OMPI_COMM_WORLD_RANK=");
  const size_t at = env.find(key);
  return at == std::string::npos ? -1 : std::atoi(env.c_str() + at + key.size());
}

// SIGKILL one rank mid-render: the job ends, the last checkpoint is whole, and a rerun
// with --resume finishes the image an uninterrupted render makes.
TEST(Mpi, AKilledRankLosesAtMostOneCheckpointAndResumeFinishes) {
  const std::string dir = compiled("killed");
  const std::string common = " scene.pbrta -q --resdiv 4 --spp 1024 --nthreads 1 --seed 2";
  const std::string line =
      "cd '" + dir + "' && (" +
      mpi(3, common + " -o k.exr --save-state k.state --checkpoint-every 0.1") +
      " > bg.out 2> bg.err; echo $? > bg.status) &";
  ASSERT_EQ(std::system(line.c_str()), 0);
  for (int i = 0; i < 600 && !fs::exists(dir + "/k.state"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_TRUE(fs::exists(dir + "/k.state")) << read_file(dir + "/bg.err");
  // Rank 1 of this job only: CTest runs other MPI tests beside this one, whose ranks work in
  // directories of their own.
  bool killed = false;
  const fs::path here = fs::canonical(dir);
  for (const auto& e : fs::directory_iterator("/proc")) {
    const std::string pid = e.path().filename().string();
    if (pid.find_first_not_of("0123456789") != std::string::npos) continue;
    if (read_file("/proc/" + pid + "/cmdline").find("pbrtrun-mpi") == std::string::npos) continue;
    std::error_code ec;
    if (fs::read_symlink("/proc/" + pid + "/cwd", ec) != here) continue;
    if (rank_of(pid) == 1) {
      ::kill(std::stoi(pid), SIGKILL);
      killed = true;
    }
  }
  ASSERT_TRUE(killed);
  for (int i = 0; i < 600 && !fs::exists(dir + "/bg.status"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_NE(read_file(dir + "/bg.status"), "0\n");
  rt::RenderState state;
  std::string error;
  ASSERT_TRUE(rt::read_render_state(dir + "/k.state", &state, &error)) << error;
  EXPECT_LT(state.samples(), 1024);
  const Outcome resumed = run_in(dir, mpi(3, common + " -o resumed.exr --resume k.state"), "re");
  ASSERT_EQ(resumed.status, 0) << resumed.err;
  const Outcome straight =
      run_in(dir, kBin + "/pbrtrun" + common + " --checkpoint-every 1000 -o straight.exr", "st");
  ASSERT_EQ(straight.status, 0) << straight.err;
  EXPECT_TRUE(same_file(dir + "/resumed.exr", dir + "/straight.exr"));
}

}  // namespace
}  // namespace testing_support
