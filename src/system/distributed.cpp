#include "system/distributed.hpp"

#include <fcntl.h>
#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <thread>

#include <fmt/format.h>

#ifdef MG_HAVE_MPI
#define OMPI_SKIP_MPICXX 1  // the C API only
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#endif

namespace mg::system {
namespace {

#ifdef MG_HAVE_MPI
/// Set by the process managers of OpenMPI (mpirun), PMIx (srun --mpi=pmix) and MPICH/Hydra.
bool started_by_launcher() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
    if (const char* v = std::getenv(name); v && *v) return true;
  return false;
}

bool mpi_running() {
  int initialized = 0, finalized = 0;
  MPI_Initialized(&initialized);
  MPI_Finalized(&finalized);
  return initialized && !finalized;
}
#endif

int local_processes = 1;

}  // namespace

int default_thread_count() {
  const int online = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  int usable = online;
  cpu_set_t set;
  CPU_ZERO(&set);
  if (::sched_getaffinity(0, sizeof set, &set) == 0) usable = std::max(1, CPU_COUNT(&set));
  // Bound to a subset: those cores are this process's. Unbound: share the machine.
  return usable < online ? usable : std::max(1, online / local_processes);
}

bool mpi_built() {
#ifdef MG_HAVE_MPI
  return true;
#else
  return false;
#endif
}

int process_rank() {
#ifdef MG_HAVE_MPI
  if (!mpi_running()) return 0;
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
#else
  return 0;
#endif
}

int process_count() {
#ifdef MG_HAVE_MPI
  if (!mpi_running()) return 1;
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  return size;
#else
  return 1;
#endif
}

ProcessGroup::ProcessGroup([[maybe_unused]] int& argc, [[maybe_unused]] char**& argv) {
#ifdef MG_HAVE_MPI
  if (!started_by_launcher()) return;
  int provided = 0;
  // Only the calling thread talks to MPI (distributed_for gathers after its pool has joined).
  if (MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) {
    std::fprintf(stderr, "minigolf: error: MPI_Init failed\n");
    std::exit(1);
  }
  active_ = true;
  MPI_Comm node;
  if (MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node) ==
      MPI_SUCCESS) {
    MPI_Comm_size(node, &local_processes);
    MPI_Comm_free(&node);
  }
  if (process_rank() != 0) {
    std::fflush(stdout);
    std::fflush(stderr);
    const int null = ::open("/dev/null", O_WRONLY);
    if (null >= 0) {
      ::dup2(null, 1);
      ::dup2(null, 2);
      ::close(null);
    }
  }
#endif
}

ProcessGroup::~ProcessGroup() { finish(0); }

int ProcessGroup::finish(int exit_code) {
#ifdef MG_HAVE_MPI
  if (!active_) return exit_code;
  active_ = false;
  std::fflush(stdout);
  std::fflush(stderr);
  if (exit_code != 0 && process_count() > 1) MPI_Abort(MPI_COMM_WORLD, exit_code);
  MPI_Finalize();
#endif
  return exit_code;
}

std::vector<std::string> all_gather(const std::string& local) {
  const int size = process_count();
  if (size == 1) return {local};
#ifdef MG_HAVE_MPI
  if (local.size() > static_cast<std::size_t>(INT_MAX))
    throw Error(fmt::format("all_gather: {} bytes exceed MPI's 2 GiB message limit", local.size()));
  const int mine = static_cast<int>(local.size());
  std::vector<int> counts(static_cast<std::size_t>(size)), offsets(static_cast<std::size_t>(size));
  MPI_Allgather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
  long total = 0;
  for (int r = 0; r < size; ++r) {
    offsets[static_cast<std::size_t>(r)] = static_cast<int>(total);
    total += counts[static_cast<std::size_t>(r)];
    if (total > INT_MAX) throw Error("all_gather: the results exceed MPI's 2 GiB message limit");
  }
  std::string buffer(static_cast<std::size_t>(total), '\0');
  MPI_Allgatherv(local.data(), mine, MPI_CHAR, buffer.data(), counts.data(), offsets.data(),
                 MPI_CHAR, MPI_COMM_WORLD);
  std::vector<std::string> out;
  for (int r = 0; r < size; ++r)
    out.push_back(buffer.substr(static_cast<std::size_t>(offsets[static_cast<std::size_t>(r)]),
                                static_cast<std::size_t>(counts[static_cast<std::size_t>(r)])));
  return out;
#else
  return {local};
#endif
}

}  // namespace mg::system
