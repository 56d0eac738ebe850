// The stopping rules, checkpoints, signals and render states as a user meets them: the
// built pbrtrun, pbrt and pbrt-merge run on the bundled default scene.
#include <signal.h>

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "command_runner.h"
#include "runtime/film/image_io.h"
#include "runtime/film/render_state.h"
#include "test_support.h"

namespace testing_support {
namespace {

namespace fs = std::filesystem;

const std::string kDefaultScene = std::string(PBRTC_SOURCE_DIR) + "/tools/default-scene/scene.pbrt";

// A fresh directory holding the default scene compiled to scene.pbrta.
std::string compiled(const std::string& name) {
  const std::string dir = scratch_dir("progressive_" + name);
  const Outcome c = run_in(dir, kBin + "/pbrtc -q '" + kDefaultScene + "' -o scene.pbrta", "pbrtc");
  EXPECT_EQ(c.status, 0) << c.err;
  return dir;
}

bool readable_image(const std::string& path) {
  rt::ImageRgb img;
  std::string error;
  return rt::read_exr(path, &img, &error) && img.width() > 0;
}

// Starts `command` in dir in the background; returns its process id.
pid_t start(const std::string& dir, const std::string& command) {
  const std::string line =
      "cd '" + dir + "' && (" + command + " > bg.stdout 2> bg.stderr & echo $! > bg.pid)";
  EXPECT_EQ(std::system(line.c_str()), 0);
  return pid_t(std::stol(read_file(dir + "/bg.pid")));
}

// Waits (up to 60 s) for a file to appear; true if it did.
bool wait_for(const std::string& path) {
  for (int i = 0; i < 600 && !fs::exists(path); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  return fs::exists(path);
}

void wait_gone(pid_t pid) {
  for (int i = 0; i < 600; ++i) {
    const std::string status = read_file("/proc/" + std::to_string(pid) + "/status");
    if (status.empty() || status.find("State:\tZ") != std::string::npos) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
}

// SIGKILL mid-render: the last checkpoint (image and state) is whole, and --resume
// finishes the very render an uninterrupted run makes.
TEST(Progressive, AKilledRenderLeavesItsLastCheckpointAndResumes) {
  const std::string dir = compiled("killed");
  const std::string common = kBin + "/pbrtrun -q scene.pbrta --resdiv 4 --nthreads 1 --spp 1024";
  const pid_t pid = start(dir, common + " -o ck.exr --save-state ck.state --checkpoint-every 0.1");
  ASSERT_TRUE(wait_for(dir + "/ck.state"));
  std::this_thread::sleep_for(std::chrono::milliseconds(150));
  ::kill(pid, SIGKILL);
  wait_gone(pid);
  EXPECT_TRUE(readable_image(dir + "/ck.exr"));
  rt::RenderState state;
  std::string error;
  ASSERT_TRUE(rt::read_render_state(dir + "/ck.state", &state, &error)) << error;
  EXPECT_GT(state.samples(), 0);
  EXPECT_LT(state.samples(), 1024);
  const Outcome resumed = run_in(dir, common + " -o resumed.exr --resume ck.state", "resume");
  ASSERT_EQ(resumed.status, 0) << resumed.err;
  const Outcome straight = run_in(dir, common + " -o straight.exr", "straight");
  ASSERT_EQ(straight.status, 0) << straight.err;
  EXPECT_EQ(read_file(dir + "/resumed.exr"), read_file(dir + "/straight.exr"));
}

// SIGINT and SIGTERM: the image so far is written, the exit status is 128 + the signal.
TEST(Progressive, SignalsWriteTheImageSoFarAndExitNonZero) {
  const std::string dir = compiled("signals");
  for (int sig : {SIGINT, SIGTERM}) {
    const std::string out = "sig" + std::to_string(sig) + ".exr";
    const pid_t pid = start(dir, "exec " + kBin +
                                     "/pbrtrun scene.pbrta --resdiv 4 --nthreads 1 --spp 100000 "
                                     "--checkpoint-every 0.2 -o " +
                                     out);
    ASSERT_TRUE(wait_for(dir + "/" + out));
    ::kill(pid, sig);
    wait_gone(pid);
    EXPECT_TRUE(readable_image(dir + "/" + out));
    EXPECT_NE(read_file(dir + "/bg.stderr").find("interrupted: wrote the image"), std::string::npos)
        << read_file(dir + "/bg.stderr");
  }
  // The exit status, through a shell that waits for it.
  const Outcome r = run_in(dir, "sh -c '" + kBin +
                                    "/pbrtrun -q scene.pbrta --resdiv 4 --nthreads 1 --spp 100000 "
                                    "-o t.exr & p=$!; sleep 1; kill -TERM $p; wait $p'");
  EXPECT_EQ(r.status, 128 + SIGTERM) << r.err;
}

TEST(Progressive, TargetErrorAndTimeLimitStopAndSaySo) {
  const std::string dir = compiled("stops");
  const Outcome t = run_in(
      dir, kBin + "/pbrtrun scene.pbrta --resdiv 4 --spp 100000 --target-error 5% --stats -o t.exr",
      "target");
  ASSERT_EQ(t.status, 0) << t.err;
  EXPECT_NE(t.err.find("target error reached"), std::string::npos) << t.err;
  EXPECT_NE(t.err.find("estimated error"), std::string::npos) << t.err;
  const Outcome l = run_in(
      dir,
      kBin + "/pbrtrun -q scene.pbrta --resdiv 4 --spp 1000000 --time-limit 1s --stats -o l.exr",
      "limit");
  ASSERT_EQ(l.status, 0) << l.err;
  EXPECT_NE(l.err.find("(time limit)"), std::string::npos) << l.err;
  EXPECT_LT(l.seconds, 30);
  // pbrt takes the same flags.
  const Outcome p = run_in(dir,
                           kBin + "/pbrt --quiet --no-cache '" + kDefaultScene +
                               "' --spp 100000 --target-error 8 --stats --outfile p.exr",
                           "pbrt");
  ASSERT_EQ(p.status, 0) << p.err;
  EXPECT_NE(p.err.find("target error reached"), std::string::npos) << p.err;
}

TEST(Progressive, BadStopValuesAreCommandLineErrors) {
  const std::string dir = compiled("bad_values");
  for (const char* flags :
       {"--target-error 0", "--target-error x", "--time-limit 10y", "--checkpoint-every -1"}) {
    const Outcome r = run_in(dir, kBin + "/pbrtrun scene.pbrta -o x.exr " + flags, "bad");
    EXPECT_EQ(r.status, 2) << flags << ": " << r.err;
    EXPECT_NE(r.err.find("error: --"), std::string::npos) << r.err;
    const Outcome p =
        run_in(dir, kBin + "/pbrt --no-cache '" + kDefaultScene + "' " + flags, "badp");
    EXPECT_EQ(p.status, 2) << flags << ": " << p.err;
  }
  EXPECT_FALSE(fs::exists(dir + "/x.exr"));
}

// pbrt-merge adds renders of different seeds and refuses what does not belong together.
TEST(Progressive, MergeJoinsSeedsAndRefusesStrangers) {
  const std::string dir = compiled("merge");
  for (int seed : {1, 2}) {
    const std::string s = std::to_string(seed);
    const Outcome r = run_in(dir,
                             kBin + "/pbrtrun -q scene.pbrta --resdiv 4 --spp 16 --seed " + s +
                                 " -o s" + s + ".exr --save-state s" + s + ".state",
                             "seed" + s);
    ASSERT_EQ(r.status, 0) << r.err;
  }
  const Outcome m =
      run_in(dir, kBin + "/pbrt-merge s1.state s2.state -o merged.exr --error-layer", "merge");
  ASSERT_EQ(m.status, 0) << m.err;
  EXPECT_NE(m.err.find("32 samples per pixel, estimated error"), std::string::npos) << m.err;
  EXPECT_TRUE(readable_image(dir + "/merged.exr"));
  // The merged pixels are the documented formula (render_state.h) over both states' sums.
  rt::RenderState sa, sb;
  rt::ImageRgb mi;
  std::string error;
  ASSERT_TRUE(rt::read_render_state(dir + "/s1.state", &sa, &error)) << error;
  ASSERT_TRUE(rt::read_render_state(dir + "/s2.state", &sb, &error)) << error;
  ASSERT_TRUE(rt::read_exr(dir + "/merged.exr", &mi, &error)) << error;
  ASSERT_EQ(mi.rgb.size(), 3 * sa.sums[0].size());
  for (size_t p = 0; p < sa.sums[0].size(); ++p) {
    double w = 0, v[3] = {0, 0, 0};
    for (const rt::RenderState* st : {&sa, &sb})
      for (int h = 0; h < 2; ++h) {
        w += st->sums[h][p].weight;
        for (int c = 0; c < 3; ++c) v[c] += st->sums[h][p].rgb[c];
      }
    for (int c = 0; c < 3; ++c)
      ASSERT_NEAR(mi.rgb[3 * p + size_t(c)], std::max(0.0, v[c] / w) * sa.scale, 1e-6) << p;
  }

  const Outcome same = run_in(dir, kBin + "/pbrt-merge s1.state s1.state -o x.exr", "same");
  EXPECT_EQ(same.status, 1);
  EXPECT_NE(same.err.find("same seed"), std::string::npos) << same.err;
  const Outcome other = run_in(dir,
                               kBin +
                                   "/pbrtrun -q scene.pbrta --resdiv 2 --spp 16 --seed 3 "
                                   "-o o.exr --save-state o.state",
                               "other");
  ASSERT_EQ(other.status, 0) << other.err;
  const Outcome res = run_in(dir, kBin + "/pbrt-merge s1.state o.state -o x.exr", "res");
  EXPECT_EQ(res.status, 1);
  EXPECT_NE(res.err.find("o.state: cannot merge: it has another resolution"), std::string::npos)
      << res.err;
  write_file(dir + "/junk.state", "not a state");
  const Outcome junk = run_in(dir, kBin + "/pbrt-merge s1.state junk.state -o x.exr", "junk");
  EXPECT_EQ(junk.status, 1);
  EXPECT_NE(junk.err.find("junk.state: not a usable render state"), std::string::npos) << junk.err;
  EXPECT_FALSE(fs::exists(dir + "/x.exr"));
}

}  // namespace
}  // namespace testing_support
