// runtime/core/code_pages.h — gives back the program code a finished phase ran.
//
// Code that has run once stays in the resident set, and Linux maps the file pages around each
// one touched as well (fault-around, 64 KiB at a time): after loading an archive and building
// Embree's BVH, megabytes of the program's and its libraries' code (Embree's builders, zstd,
// the archive reader...) are resident that rendering never runs again, and they count in the
// render's peak memory. release_code_pages() drops them: the pages of every loaded object's
// segments that are never written (PT_LOAD without PF_W, outside PT_GNU_RELRO, in objects
// without text relocations) leave the resident set (MADV_DONTNEED). They are unmodified file
// pages, so whatever runs next maps its own again from the page cache, unchanged; nothing
// else is touched. Skipped under a debugger, whose breakpoints are private copies of code
// pages that the call would drop: false then.
#pragma once

namespace rt {

bool release_code_pages();

}  // namespace rt
