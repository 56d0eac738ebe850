// tests/compiler/schema_doc_test.cpp — format/SCHEMA.md is what the code's schema says.
//
// The archive spec points readers at SCHEMA.md for each type's parameter order; a schema change
// without regenerating it (pbrtc --print-schema > format/SCHEMA.md) fails here.
#include <gtest/gtest.h>

#include <sstream>

#include "compiler/archive_info.h"
#include "test_support.h"

namespace pbrtc {
namespace {

TEST(SchemaDoc, SchemaMarkdownMatchesTheTables) {
  std::ostringstream out;
  print_schema_markdown(out);
  std::string doc = testing_support::read_file(PBRTC_SOURCE_DIR "/format/SCHEMA.md");
  ASSERT_FALSE(doc.empty()) << "format/SCHEMA.md is missing";
  EXPECT_TRUE(doc == out.str())
      << "format/SCHEMA.md is out of date: run pbrtc --print-schema > format/SCHEMA.md";
}

}  // namespace
}  // namespace pbrtc
