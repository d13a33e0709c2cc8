// Test support: finding the real compilers, running them, and counting the arithmetic
// instructions of what they emit (PTX text, `cuobjdump -sass` text, SPIR-V binaries).
#pragma once

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

namespace shaderfit::testing {

inline int run_command(const std::string& command, std::string* output = nullptr) {
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return -1;
  std::string text;
  char buf[4096];
  for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, pipe)) > 0;) text.append(buf, n);
  const int status = ::pclose(pipe);
  if (output) *output = std::move(text);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

inline bool executable(const std::filesystem::path& p) {
  return std::filesystem::is_regular_file(p) && ::access(p.c_str(), X_OK) == 0;
}

// Folders where pip puts the CUDA tool wheels (nvidia-cuda-cuobjdump, nvidia-cuda-nvdisasm):
// <site-packages>/nvidia/cu13/bin (or cuNN for other CUDA majors).
inline std::vector<std::filesystem::path> pip_cuda_bin_dirs() {
  static const std::vector<std::filesystem::path> dirs = [] {
    std::vector<std::filesystem::path> out;
    std::string text;
    const std::string py =
        "python3 -c \"import site, sysconfig; print(sysconfig.get_paths()['purelib']); "
        "print(site.getusersitepackages()); [print(p) for p in site.getsitepackages()]\"";
    if (run_command(py, &text) != 0) return out;
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);) {
      const std::filesystem::path nvidia = std::filesystem::path(line) / "nvidia";
      std::error_code ec;
      if (!std::filesystem::is_directory(nvidia, ec)) continue;
      for (const auto& entry : std::filesystem::directory_iterator(nvidia, ec))
        if (std::filesystem::is_directory(entry.path() / "bin")) out.push_back(entry.path() / "bin");
    }
    return out;
  }();
  return dirs;
}

// The tool's path: $PATH, then /usr/local/cuda/bin, then the pip CUDA wheels; nullopt if absent.
inline std::optional<std::string> find_tool(const std::string& name) {
  std::vector<std::filesystem::path> dirs;
  if (const char* path = std::getenv("PATH")) {
    std::istringstream parts(path);
    for (std::string d; std::getline(parts, d, ':');)
      if (!d.empty()) dirs.emplace_back(d);
  }
  dirs.emplace_back("/usr/local/cuda/bin");
  if (name == "cuobjdump" || name == "nvdisasm")
    for (const auto& d : pip_cuda_bin_dirs()) dirs.push_back(d);
  for (const auto& d : dirs)
    if (executable(d / name)) return (d / name).string();
  return std::nullopt;
}

// The C++ compilers present among g++ and clang++, as (name, path); each missing one is said
// ("skipped: clang++ not found").
inline std::vector<std::pair<std::string, std::string>> cpp_compilers() {
  std::vector<std::pair<std::string, std::string>> out;
  for (const char* name : {"g++", "clang++"}) {
    if (const auto path = find_tool(name))
      out.emplace_back(name, *path);
    else
      std::printf("skipped: %s not found\n", name);
  }
  return out;
}

// A fresh folder for one test's files.
inline std::filesystem::path scratch_folder(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("shaderfit_compiler_" + std::to_string(::getpid())) / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

inline void write_text(const std::filesystem::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

inline std::string read_text(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

inline bool starts_with(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

// Arithmetic instructions per .entry of PTX: float operations (add sub mul fma neg abs div rcp
// rsqrt sqrt ex2 lg2 sin cos tanh min max copysign, cvt.sat to f32, and set/select on f32).
// Moves, loads, stores, address and integer arithmetic are not counted.
inline std::map<std::string, int> count_ptx(const std::string& ptx) {
  std::map<std::string, int> counts;
  std::string current;
  std::istringstream lines(ptx);
  static const char* kOps[] = {"add.",   "sub.", "mul.",      "fma.",  "neg.",  "abs.",
                               "div.",   "rcp.", "rsqrt.",    "sqrt.", "ex2.",  "lg2.",
                               "sin.",   "cos.", "min.",      "max.",  "setp.", "selp.",
                               "testp.", "mad.", "copysign.", "tanh."};
  for (std::string line; std::getline(lines, line);) {
    if (line.find(".entry") != std::string::npos) {
      std::istringstream words(line.substr(line.find(".entry") + 6));
      words >> current;
      current = current.substr(0, current.find('('));
      counts[current] = 0;
      continue;
    }
    if (current.empty()) continue;
    std::istringstream words(line);
    std::string op;
    words >> op;
    if (op.empty() || op[0] == '@') words >> op;
    if (op.find(".f32") == std::string::npos) continue;
    bool arith = starts_with(op, "cvt.") && op.find(".sat") != std::string::npos;
    for (const char* k : kOps) arith = arith || starts_with(op, k);
    if (arith) ++counts[current];
  }
  return counts;
}

// Arithmetic instructions per function of `cuobjdump -sass` output: FADD FMUL FFMA FMNMX MUFU,
// float compares/selects and LOP3 (the bit operations of copysign and sign; the kernels' address
// arithmetic is IMAD). Moves (MOV, HFMA2.MMA used as a move) are not counted, nor the code after
// the function's EXIT: out-of-line subroutines such as the slow path of an IEEE division
// (atan2f's), which runs only for quotients beyond float's normal range.
inline std::map<std::string, int> count_sass(const std::string& dump) {
  std::map<std::string, int> counts;
  std::string current;
  bool exited = false;
  std::istringstream lines(dump);
  for (std::string line; std::getline(lines, line);) {
    const auto f = line.find("Function : ");
    if (f != std::string::npos) {
      current = line.substr(f + 11);
      while (!current.empty() && std::isspace(static_cast<unsigned char>(current.back()))) current.pop_back();
      counts[current] = 0;
      exited = false;
      continue;
    }
    const auto close = line.find("*/");
    if (current.empty() || exited || line.find("/*") == std::string::npos ||
        close == std::string::npos)
      continue;
    std::istringstream words(line.substr(close + 2));
    std::string op;
    words >> op;
    const bool predicated = !op.empty() && op[0] == '@';
    if (predicated) words >> op;
    if (op == "EXIT" && !predicated) exited = true;  // the end of the function's own code
    for (const char* k : {"FADD", "FMUL", "FFMA", "FMNMX", "MUFU", "FSETP", "FSEL", "FSET", "FRND",
                          "FCHK", "LOP3"}) {
      if (starts_with(op, k)) {
        ++counts[current];  // once: FSETP also starts with FSET
        break;
      }
    }
  }
  return counts;
}

// SASS counts (count_sass) of a cubin through cuobjdump. Absent: cuobjdump is not installed, and
// the caller skips its SASS checks; Failed: cuobjdump is installed but failed (its messages in
// *log), which fails the caller's test instead of silently dropping the SASS checks.
enum class SassDump { Done, Absent, Failed };
inline SassDump dump_sass(const std::filesystem::path& cubin, std::map<std::string, int>* counts,
                          std::string* log) {
  const auto cuobjdump = find_tool("cuobjdump");
  if (!cuobjdump) return SassDump::Absent;
  std::string dump;
  if (run_command("'" + *cuobjdump + "' -sass '" + cubin.string() + "'", &dump) != 0) {
    *log = "cuobjdump failed on " + cubin.string() + ":\n" + dump;
    return SassDump::Failed;
  }
  *counts = count_sass(dump);
  return SassDump::Done;
}

// Arithmetic SPIR-V instructions per function (named by its OpName up to the '(' of glslang's
// mangling): OpFNegate OpFAdd OpFSub OpFMul OpFDiv OpFRem OpFMod OpVectorTimesScalar OpDot,
// every OpExtInst (GLSL.std.450 sqrt, exp2, fma, clamp, ...), the ordered float comparisons,
// OpSelect and the bitwise AND and OR (bitcasts are not counted).
inline std::map<std::string, int> count_spirv(const std::string& binary) {
  std::map<std::string, int> counts;
  std::vector<std::uint32_t> w(binary.size() / 4);
  std::memcpy(w.data(), binary.data(), w.size() * 4);
  if (w.size() < 5 || w[0] != 0x07230203u) return counts;
  std::map<std::uint32_t, std::string> names;
  std::string current;
  for (std::size_t i = 5; i < w.size();) {
    const std::uint32_t count = w[i] >> 16, op = w[i] & 0xffffu;
    if (count == 0 || i + count > w.size()) break;
    if (op == 5) {  // OpName
      const char* s = reinterpret_cast<const char*>(&w[i + 2]);
      std::string name(s, strnlen(s, (count - 2) * 4));
      names[w[i + 1]] = name.substr(0, name.find('('));
    } else if (op == 54) {  // OpFunction
      current = names[w[i + 2]];
      counts[current] += 0;
    } else if (op == 56) {  // OpFunctionEnd
      current.clear();
    } else if (!current.empty()) {
      for (std::uint32_t a : {127u, 129u, 131u, 133u, 136u, 140u, 141u, 142u, 148u, 12u, 169u, 184u,
                              186u, 188u, 190u, 197u, 199u})
        if (op == a) ++counts[current];
    }
    i += count;
  }
  return counts;
}

}  // namespace shaderfit::testing
