// tools/accuracy/sweep_csv.h — a sweep's rows as CSV.
//
// Header "scene,config,spp,seconds,relmse,rmse,mare,render_seconds,estimated_error"
// (the render's own estimate of sqrt(relmse), -1 where it has none), then one
// line per row in order; numbers in %.6g (seconds) and %.6e (errors), so a
// spreadsheet or a script reads them without loss that matters. Names never
// hold commas (configuration names are "/"-joined words; scene names come
// from file names, and a comma there is replaced by "_").
#pragma once

#include <string>
#include <vector>

#include "tools/accuracy/sweep.h"

namespace accuracy {

extern const char kCsvHeader[];

std::string sweep_csv(const std::vector<SweepRow>& rows);

// Writes sweep_csv(rows) to path; false with *error naming the file.
bool write_sweep_csv(const std::string& path, const std::vector<SweepRow>& rows,
                     std::string* error);

}  // namespace accuracy
