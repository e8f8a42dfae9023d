// Shared by the libFuzzer targets: the input as a file with a chosen extension (the loaders read
// files), removed again when the holder goes.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace relief::fuzz {

class TempFile {
 public:
  TempFile(const uint8_t* data, size_t size, const std::string& extension) {
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("relief_fuzz_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    path_ = (dir / ("input" + extension)).string();
    std::ofstream f(path_, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  ~TempFile() { std::remove(path_.c_str()); }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace relief::fuzz
