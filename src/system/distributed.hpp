#pragma once
/// Scale-out over processes with MPI (optional at build time; docs/architecture.md).
///
/// Started by an MPI launcher (`mpirun -np N minigolf ...`, `srun --mpi=pmix minigolf ...`), every
/// process runs the whole command on the same inputs; only the independent jobs of
/// `distributed_for` are split: process r runs the jobs r, r + N, r + 2N, ... on its own thread
/// pool, and then every process receives every result (bit for bit, system/wire.hpp), so all
/// processes continue with the same state and the output is the same bits as one process. Rank 0
/// prints; the others are silent (their stdout and stderr go to /dev/null). Files are written by
/// every process with the same content (atomically: a shared file system sees one whole file).
///
/// Without MPI, or outside a launcher, there is one process and `distributed_for` is
/// `parallel_for`; so it is inside a job of another parallel_for (nested loops run locally).
#include <functional>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "system/parallel.hpp"
#include "system/wire.hpp"

namespace mg::system {

/// True when the project was built with MPI (MG_HAVE_MPI).
bool mpi_built();
/// This process's rank (0 outside an MPI run) and the number of processes (1 outside one).
int process_rank();
int process_count();
inline bool is_root_process() { return process_rank() == 0; }

/// Joins the MPI run when the program was started by an MPI launcher (one per program, in
/// `main`, before anything else). Ranks > 0 are silenced.
class ProcessGroup {
 public:
  ProcessGroup(int& argc, char**& argv);
  ~ProcessGroup();
  ProcessGroup(const ProcessGroup&) = delete;
  ProcessGroup& operator=(const ProcessGroup&) = delete;
  /// Leaves the run and returns `exit_code`. A failed process of a run of several aborts the
  /// whole run with that code instead (the others may be waiting for it).
  int finish(int exit_code);

 private:
  bool active_ = false;
};

/// Every process's `local` bytes, in rank order (collective: every process must call it).
std::vector<std::string> all_gather(const std::string& local);

/// parallel_for over the processes of the run: job(i, data) fills results[i] for i in
/// [0, results.size()); afterwards every process holds every result. `done(i)` is called after
/// each local job (completion order), then for the other processes' jobs in index order once
/// their results are in. An error of any job is thrown on every process (the lowest failing
/// rank's, with its type).
template <typename T, typename Job>
void distributed_for(const System& system, std::vector<T>& results, int threads, Job job,
                     const std::function<void(int)>& done = {}) {
  const int n = static_cast<int>(results.size());
  const int size = process_count(), rank = process_rank();
  if (size == 1 || inside_parallel_job()) {
    parallel_for(system, n, threads, job, done);
    return;
  }
  const auto local_count = [&](int r) { return n > r ? (n - r + size - 1) / size : 0; };
  int kind = 0;  // 0 ok, 1 InputError, 2 IoError, 3 NumericalError, 4 other
  std::string message;
  try {
    std::function<void(int)> local_done;
    if (done) local_done = [&](int k) { done(rank + k * size); };
    parallel_for(
        system, local_count(rank), threads,
        [&](int k, SystemData& data) { job(rank + k * size, data); }, local_done);
  } catch (const InputError& e) {
    kind = 1, message = e.what();
  } catch (const IoError& e) {
    kind = 2, message = e.what();
  } catch (const NumericalError& e) {
    kind = 3, message = e.what();
  } catch (const std::exception& e) {
    kind = 4, message = e.what();
  }
  WireWriter w;
  w(kind, message);
  if (kind == 0)
    for (int k = 0; k < local_count(rank); ++k)
      w(results[static_cast<std::size_t>(rank + k * size)]);
  const std::vector<std::string> all = all_gather(w.bytes());
  for (int r = 0; r < size; ++r) {
    WireReader in(all[static_cast<std::size_t>(r)]);
    in(kind, message);
    switch (kind) {
      case 0:
        break;
      case 1:
        throw InputError(message);
      case 2:
        throw IoError(message);
      case 3:
        throw NumericalError(message);
      default:
        throw Error(message);
    }
    if (r == rank) continue;
    for (int k = 0; k < local_count(r); ++k) in(results[static_cast<std::size_t>(r + k * size)]);
    if (!in.at_end())
      throw Error("distributed_for: a message from another process has extra bytes");
  }
  if (done)
    for (int i = 0; i < n; ++i)
      if (i % size != rank) done(i);
}

}  // namespace mg::system
