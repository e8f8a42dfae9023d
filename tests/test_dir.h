// A temporary folder of the running test's own, for fixtures that write files.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

namespace relief::test {

// temp/<prefix>_<pid>_<test name>: distinct for every test and every test process.
inline std::filesystem::path test_dir_path(const std::string& prefix) {
  return std::filesystem::temp_directory_path() /
         (prefix + "_" + std::to_string(::getpid()) + "_" +
          ::testing::UnitTest::GetInstance()->current_test_info()->name());
}

// test_dir_path(prefix), emptied and created.
inline std::filesystem::path fresh_test_dir(const std::string& prefix) {
  const std::filesystem::path dir = test_dir_path(prefix);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace relief::test

// `name` in the test's temporary folder (gtest's TempDir, shared by the tests of a process).
inline std::string tmp(const std::string& name) {
  return (std::filesystem::path(::testing::TempDir()) / name).string();
}
