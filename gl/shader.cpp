#include "gl/shader.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include <epoxy/gl.h>

#include "gl/embedded_shaders.h"

namespace relief::gl {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> shader_dirs() {
  std::vector<fs::path> dirs;
  if (const char* env = std::getenv("RELIEF_GL_SHADER_DIR"); env && *env) dirs.emplace_back(env);
#ifdef RELIEF_GL_SHADER_DIR
  dirs.emplace_back(RELIEF_GL_SHADER_DIR);
#endif
  return dirs;
}

bool valid_name(const std::string& name) {
  return !name.empty() && name.find('/') == std::string::npos &&
         name.find("..") == std::string::npos;
}

bool is_shader_name(const std::string& name) {
  for (const char* ext : {".vert", ".frag", ".glsl"})
    if (name.size() > 5 && name.compare(name.size() - 5, 5, ext) == 0) return true;
  return false;
}

}  // namespace

Result<std::string> read_shader_file(const std::string& name) {
  if (!valid_name(name)) return Status::error("bad shader file name \"" + name + "\"");
  for (const fs::path& dir : shader_dirs()) {
    const fs::path p = dir / name;
    std::error_code ec;
    if (!fs::is_regular_file(p, ec)) continue;
    std::ifstream in(p, std::ios::binary);
    if (!in) return Status::error(p.string() + ": cannot open");
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
  for (const EmbeddedShader& e : embedded_shaders())
    if (name == e.name) return std::string(e.text, e.size);
  std::string where;
  for (const fs::path& dir : shader_dirs()) where += (where.empty() ? "" : ", ") + dir.string();
  return Status::error("shader file \"" + name + "\" not found (searched " +
                       (where.empty() ? std::string("embedded copies") : where + ", embedded") +
                       ")");
}

bool shader_file_exists(const std::string& name) {
  if (!valid_name(name)) return false;
  for (const fs::path& dir : shader_dirs()) {
    std::error_code ec;
    if (fs::is_regular_file(dir / name, ec)) return true;
  }
  for (const EmbeddedShader& e : embedded_shaders())
    if (name == e.name) return true;
  return false;
}

std::vector<std::string> list_shader_files() {
  std::set<std::string> names;
  for (const fs::path& dir : shader_dirs()) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) continue;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
      const std::string n = entry.path().filename().string();
      if (entry.is_regular_file() && is_shader_name(n)) names.insert(n);
    }
    break;  // the first existing directory wins, as in read_shader_file
  }
  if (names.empty())
    for (const EmbeddedShader& e : embedded_shaders()) names.insert(e.name);
  return {names.begin(), names.end()};
}

std::string shader_source_location() {
  for (const fs::path& dir : shader_dirs()) {
    std::error_code ec;
    if (fs::is_directory(dir, ec)) return dir.string();
  }
  return "embedded";
}

Result<ShaderSource> preprocess_shader(const std::string& name, const std::string& text,
                                       const std::vector<std::string>& defines,
                                       const ShaderReader& read) {
  ShaderSource out;
  std::set<std::string> included;
  std::vector<std::string> stack;
  std::ostringstream dst;
  bool seen_version = false;

  // Emits `content` of file `fname` as source string `id`.
  std::function<Status(const std::string&, const std::string&)> emit =
      [&](const std::string& fname, const std::string& content) -> Status {
    const int id = static_cast<int>(out.files.size());
    out.files.push_back(fname);
    stack.push_back(fname);
    std::istringstream in(content);
    std::string line;
    int lineno = 0;
    if (id != 0) dst << "#line 1 " << id << "\n";
    while (std::getline(in, line)) {
      ++lineno;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      const size_t first = line.find_first_not_of(" \t");
      const std::string trimmed = first == std::string::npos ? "" : line.substr(first);
      if (trimmed.rfind("#version", 0) == 0) {
        if (id != 0 || seen_version)
          return Status::error(fname + ":" + std::to_string(lineno) +
                               ": #version only in the main file");
        seen_version = true;
        dst << line << "\n";
        for (const std::string& d : defines) dst << "#define " << d << "\n";
        dst << "#line " << lineno + 1 << " " << id << "\n";
        continue;
      }
      if (trimmed.rfind("#include", 0) == 0) {
        const size_t q0 = trimmed.find('"');
        const size_t q1 = q0 == std::string::npos ? q0 : trimmed.find('"', q0 + 1);
        if (q1 == std::string::npos)
          return Status::error(fname + ":" + std::to_string(lineno) + ": malformed #include");
        const std::string inc = trimmed.substr(q0 + 1, q1 - q0 - 1);
        if (std::find(stack.begin(), stack.end(), inc) != stack.end())
          return Status::error(fname + ":" + std::to_string(lineno) +
                               ": #include cycle through \"" + inc + "\"");
        if (included.insert(inc).second) {
          Result<std::string> content2 = read(inc);
          if (!content2.ok())
            return content2.status().with_context(fname + ":" + std::to_string(lineno));
          RELIEF_RETURN_IF_ERROR(emit(inc, *content2));
          dst << "\n#line " << lineno + 1 << " " << id << "\n";
        } else {
          dst << "\n";
        }
        continue;
      }
      if (!seen_version && id == 0 && !trimmed.empty() && trimmed.rfind("//", 0) != 0)
        return Status::error(fname + ":" + std::to_string(lineno) +
                             ": the first directive must be #version");
      dst << line << "\n";
    }
    stack.pop_back();
    return {};
  };
  RELIEF_RETURN_IF_ERROR(emit(name, text));
  if (!seen_version) return Status::error(name + ": no #version line");
  out.text = dst.str();
  return out;
}

std::string format_shader_log(const std::string& log, const std::vector<std::string>& files) {
  std::istringstream in(log);
  std::string line, first_line;
  // Mesa: "0:12(3): error: msg"; NVIDIA: "0(12) : error C0000: msg"; AMD: "ERROR: 0:12: msg".
  static const std::regex mesa(R"(^\s*(\d+):(\d+)\(\d+\):\s*(.*)$)");
  static const std::regex nvidia(R"(^\s*(\d+)\((\d+)\)\s*:\s*(.*)$)");
  static const std::regex amd(R"(^\s*(?:ERROR|WARNING):\s*(\d+):(\d+):\s*(.*)$)");
  std::string fallback;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    if (first_line.empty()) first_line = line;
    std::smatch m;
    if (std::regex_match(line, m, mesa) || std::regex_match(line, m, nvidia) ||
        std::regex_match(line, m, amd)) {
      const size_t id = std::stoul(m[1].str());
      const std::string file = id < files.size() ? files[id] : "source " + m[1].str();
      std::string formatted = file + ":" + m[2].str() + ": " + m[3].str();
      // Errors before warnings.
      if (line.find("error") != std::string::npos || line.find("ERROR") != std::string::npos)
        return formatted;
      if (fallback.empty()) fallback = formatted;
    }
  }
  if (!fallback.empty()) return fallback;
  return first_line.empty() ? std::string("(empty log)") : first_line;
}

Result<unsigned> compile_shader(unsigned stage, const ShaderSource& source) {
  const GLuint shader = glCreateShader(stage);
  if (shader == 0) return Status::error("glCreateShader failed");
  const char* text = source.text.c_str();
  const GLint length = static_cast<GLint>(source.text.size());
  glShaderSource(shader, 1, &text, &length);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok) return static_cast<unsigned>(shader);
  GLint len = 0;
  glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &len);
  std::string log(static_cast<size_t>(std::max(len, 1)), '\0');
  glGetShaderInfoLog(shader, static_cast<GLsizei>(log.size()), nullptr, log.data());
  glDeleteShader(shader);
  log.resize(std::strlen(log.c_str()));
  return Status::error("GLSL compile error: " + format_shader_log(log, source.files));
}

Result<unsigned> link_program(const std::vector<unsigned>& shaders, const std::string& label) {
  const GLuint program = glCreateProgram();
  for (unsigned s : shaders) glAttachShader(program, s);
  glLinkProgram(program);
  for (unsigned s : shaders) glDetachShader(program, s);
  GLint ok = GL_FALSE;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (ok) return static_cast<unsigned>(program);
  GLint len = 0;
  glGetProgramiv(program, GL_INFO_LOG_LENGTH, &len);
  std::string log(static_cast<size_t>(std::max(len, 1)), '\0');
  glGetProgramInfoLog(program, static_cast<GLsizei>(log.size()), nullptr, log.data());
  glDeleteProgram(program);
  log.resize(std::strlen(log.c_str()));
  std::string first = log.substr(0, log.find('\n'));
  return Status::error("GLSL link error (" + label +
                       "): " + (first.empty() ? "(empty log)" : first));
}

Result<unsigned> build_program(const std::string& vertex_file, const std::string& fragment_file,
                               const std::vector<std::string>& defines) {
  std::vector<unsigned> shaders;
  auto cleanup = [&] {
    for (unsigned s : shaders) glDeleteShader(s);
  };
  for (auto [stage, file] : {std::pair<GLenum, const std::string*>{GL_VERTEX_SHADER, &vertex_file},
                             {GL_FRAGMENT_SHADER, &fragment_file}}) {
    Result<std::string> text = read_shader_file(*file);
    if (!text.ok()) {
      cleanup();
      return text.status();
    }
    Result<ShaderSource> src = preprocess_shader(*file, *text, defines);
    if (!src.ok()) {
      cleanup();
      return src.status();
    }
    Result<unsigned> s = compile_shader(stage, *src);
    if (!s.ok()) {
      cleanup();
      return s.status();
    }
    shaders.push_back(*s);
  }
  Result<unsigned> program = link_program(shaders, vertex_file + " + " + fragment_file);
  cleanup();
  return program;
}

}  // namespace relief::gl
