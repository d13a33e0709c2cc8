// Helpers of the tests that run shaderfit-mpi under mpirun (SHADERFIT_MPIEXEC and
// SHADERFIT_MPI_PATH come from cmake/mpi.cmake).
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <string>

namespace shaderfit::mpi_testing {

// `name` in this test process's own temporary directory (created).
inline std::filesystem::path scratch(const std::string& name) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("shaderfit_mpi_test_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  return dir / name;
}

struct Outcome {
  int status = -1;
  std::string output;  // stdout and stderr
};

inline Outcome run(const std::string& command) {
  Outcome r;
  FILE* p = popen((command + " 2>&1").c_str(), "r");
  if (p == nullptr) return r;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, p) != nullptr) r.output += buffer;
  const int s = pclose(p);
  r.status = WIFEXITED(s) ? WEXITSTATUS(s) : -1;
  return r;
}

// mpirun for the tests: as root too (CI), any number of ranks on few cores, and without the
// shared-memory single-copy mechanism that containers often forbid; with `recovery`, a rank that
// dies does not end the job (docs/batch.md).
inline std::string mpirun(int ranks, bool recovery = false) {
  return std::string(
             "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
             "OMPI_MCA_btl_vader_single_copy_mechanism=none "
             "OMPI_MCA_rmaps_base_oversubscribe=1 ") +
         (recovery ? "OMPI_MCA_orte_enable_recovery=1 " : "") + SHADERFIT_MPIEXEC + " -np " +
         std::to_string(ranks) + " " + SHADERFIT_MPI_PATH;
}

// Why two ranks cannot run here ("" when they can): no mpirun, or one that fails to start them
// (a sandbox without shared memory, say).
inline const std::string& cannot_run_ranks() {
  static const std::string why = [] {
    if (!std::filesystem::exists(SHADERFIT_MPIEXEC) && run("command -v mpirun").status != 0)
      return std::string("mpirun not found");
    const Outcome r = run(mpirun(2) + " --version");
    if (r.status == 0) return std::string();
    return "mpirun cannot start 2 ranks here: " + r.output.substr(0, r.output.find('\n'));
  }();
  return why;
}

}  // namespace shaderfit::mpi_testing

#define REQUIRE_MPIRUN()                                   \
  if (!shaderfit::mpi_testing::cannot_run_ranks().empty()) \
  GTEST_SKIP() << "skipped: " << shaderfit::mpi_testing::cannot_run_ranks()
