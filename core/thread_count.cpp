#include "core/thread_count.h"

#include <omp.h>
#include <pthread.h>

#include <cctype>
#include <cstdlib>
#include <vector>

namespace rfidray {
namespace {

// OMP_STACKSIZE as OpenMP 5 §6.6 reads it: a number with an optional unit B, K, M or G (default K). 0 when unset
// or not of that form (the pthread default is then probed, as libgomp then uses).
size_t openmp_stack_bytes() {
  for (const char* name : {"OMP_STACKSIZE", "GOMP_STACKSIZE"}) {
    const char* text = std::getenv(name);
    if (!text || !*text) continue;
    char* end = nullptr;
    const double v = std::strtod(text, &end);
    while (*end && std::isspace(static_cast<unsigned char>(*end))) ++end;
    double unit = 1024.0;
    switch (std::toupper(static_cast<unsigned char>(*end))) {
      case 'B': unit = 1.0; break;
      case 'K': unit = 1024.0; break;
      case 'M': unit = 1024.0 * 1024.0; break;
      case 'G': unit = 1024.0 * 1024.0 * 1024.0; break;
      case '\0': break;
      default: return 0;
    }
    if (v > 0.0 && v * unit < 1e15) return static_cast<size_t>(v * unit);
  }
  return 0;
}

struct Gate {
  pthread_mutex_t mutex = PTHREAD_MUTEX_INITIALIZER;
  pthread_cond_t open = PTHREAD_COND_INITIALIZER;
  bool opened = false;
};

// Each probe thread holds its stack until all were created, as an OpenMP team does.
void* wait_at(void* arg) {
  Gate* g = static_cast<Gate*>(arg);
  pthread_mutex_lock(&g->mutex);
  while (!g->opened) pthread_cond_wait(&g->open, &g->mutex);
  pthread_mutex_unlock(&g->mutex);
  return nullptr;
}

// How many of `extra` threads could be created at once (they are joined before returning).
int probe(int extra) {
  pthread_attr_t attr;
  pthread_attr_init(&attr);
  if (const size_t stack = openmp_stack_bytes()) pthread_attr_setstacksize(&attr, stack);
  Gate gate;
  std::vector<pthread_t> started;
  started.reserve(static_cast<size_t>(extra));
  for (int i = 0; i < extra; ++i) {
    pthread_t t;
    if (pthread_create(&t, &attr, wait_at, &gate) != 0) break;
    started.push_back(t);
  }
  pthread_mutex_lock(&gate.mutex);
  gate.opened = true;
  pthread_cond_broadcast(&gate.open);
  pthread_mutex_unlock(&gate.mutex);
  for (pthread_t t : started) pthread_join(t, nullptr);
  pthread_attr_destroy(&attr);
  return static_cast<int>(started.size());
}

}  // namespace

ThreadCount startable_threads(int requested, const std::string& option) {
  ThreadCount out;
  const int wanted = requested > 0 ? requested : omp_get_max_threads();
  const int started = 1 + probe(wanted - 1);
  if (started >= wanted) {
    out.threads = wanted;
    return out;
  }
  out.threads = std::max(1, started / 2);
  out.note = option + " " + std::to_string(wanted) + ": this process could start only " + std::to_string(started) +
             " threads (its address-space or thread limit); using " + std::to_string(out.threads) +
             " (results are the same at any thread count)";
  return out;
}

}  // namespace rfidray
