// pbrtc — the pbrt-v3 scene compiler's command line.
//
// pbrtc --check FILE...   parse and validate, print a summary per scene.
// Diagnostics go to stderr as "path:line:col: error: message"; the exit code
// is 0 only if every file compiled without errors.
#include <CLI/CLI.hpp>

#include <iostream>

#include "compiler/diagnostics.h"
#include "compiler/scene_builder.h"
#include "compiler/summary.h"

int main(int argc, char** argv) {
  CLI::App app{"pbrtc: compiles pbrt-v3 scenes into validated binary scene archives"};
  std::vector<std::string> inputs;
  bool check = false, werror = false, quiet = false;
  int max_errors = 20;
  app.add_option("scene", inputs, "pbrt-v3 scene files (\"-\" or none: standard input)");
  app.add_flag("--check", check, "parse and validate only; print a summary of each scene");
  app.add_flag("--Werror", werror, "treat warnings as errors");
  app.add_flag("-q,--quiet", quiet, "print only errors and warnings");
  app.add_option("--max-errors", max_errors, "stop after this many errors (default 20)")
      ->check(CLI::PositiveNumber);
  app.set_version_flag("--version", "pbrtc 0.1.0");
  CLI11_PARSE(app, argc, argv);

  if (inputs.empty()) inputs.push_back("-");
  if (!check) {
    std::cerr << "pbrtc: error: writing archives is not implemented yet; use --check\n";
    return 2;
  }
  bool all_ok = true;
  for (const std::string& path : inputs) {
    pbrtc::SourceFiles files;
    pbrtc::Diagnostics diag(&files, &std::cerr);
    diag.werror = werror;
    diag.max_errors = max_errors;
    pbrtc::SceneDesc scene;
    bool ok = pbrtc::build_scene(path, &files, &diag, &scene);
    if (diag.should_stop())
      std::cerr << path << ": too many errors (" << diag.error_count() << "), stopping\n";
    if (!ok) {
      all_ok = false;
      std::cerr << path << ": " << diag.error_count() << " error"
                << (diag.error_count() == 1 ? "" : "s") << ", " << diag.warning_count()
                << " warning" << (diag.warning_count() == 1 ? "" : "s") << "\n";
      continue;
    }
    if (!quiet) pbrtc::print_summary(std::cout, path, scene);
  }
  return all_ok ? 0 : 1;
}
