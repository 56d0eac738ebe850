// runtime/render/pbrtrun_cli.h — pbrtrun's command line, shared by pbrtrun and pbrtrun-mpi.
//
// add_options() declares every option on a CLI11 app (the archive, output, overrides,
// stopping rules, states); to_job() checks what CLI11 cannot (crop window order, the
// stop values' units, --shard's K/N and its need for --save-state) and fills the
// RenderJobOptions, or gives the message for exit code 2.
#pragma once

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "runtime/render/render_job.h"

namespace rt {

struct PbrtrunArgs {
  std::string input, outfile, preview;
  int spp = 0, resdiv = 1, nthreads = 0, differential_spp = 0;
  uint64_t seed = 0;
  std::vector<float> crop;
  bool quiet = false, show_stats = false, watertight = false, error_layer = false;
  std::string target_error, time_limit, checkpoint_every, save_state, resume, shard;
};

void add_options(CLI::App* app, PbrtrunArgs* args);
[[nodiscard]] bool to_job(const PbrtrunArgs& args, RenderJobOptions* job, std::string* error);

}  // namespace rt
