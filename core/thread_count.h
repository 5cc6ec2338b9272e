#pragma once
// How many OpenMP threads a run can use. OpenMP ends the whole process when it cannot create a thread
// (libgomp: "Thread creation failed", exit status 1) — e.g. `--threads 1000` under an address-space limit, at
// 8 MiB of stack per thread — so a requested count is checked first by starting that many threads.
// Not thread-safe with respect to other thread creation in the process (call it from the main thread, before a
// parallel region); throws nothing.
#include <string>

namespace rfidray {

struct ThreadCount {
  int threads = 1;   // what the run uses (≥ 1)
  std::string note;  // empty when the request is used as given; else what was used and why
};

// `requested` threads (0: OpenMP's default, omp_get_max_threads()) when this process can start them: requested − 1
// threads (the caller's thread is the first) are started with the stack size OpenMP gives its threads
// (OMP_STACKSIZE or GOMP_STACKSIZE, else the default of pthread_create) and joined. When only k < requested could
// start, half of them (≥ 1) is used — the run needs address space for its own data too — and `note` names
// `option`, what was asked and what is used.
ThreadCount startable_threads(int requested, const std::string& option);

}  // namespace rfidray
