// The source tree's root, for the tests that read its models and data files. Only
// source_dir.cpp is compiled with the path itself, so that no other test's compilation depends
// on where the tree is checked out (a compiler cache then serves any checkout).
#pragma once

namespace puppet::test {
const char* source_dir();
}  // namespace puppet::test

#define PUPPET_SOURCE_DIR ::puppet::test::source_dir()
