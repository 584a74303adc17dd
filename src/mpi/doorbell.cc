// The node's doorbells: futex words in an MPI shared-memory window, rung by senders, slept on by waiters.
#include "mpi/doorbell.h"

#include <linux/futex.h>
#include <mpi.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <climits>
#include <ctime>
#include <vector>

namespace gdp::mpi {
namespace {

// A rank's doorbell, a cache line of its own. `count` is the futex word (not a private futex: the
// ranks are processes); `sleepers` spares the sender a system call when no thread sleeps.
struct alignas(64) Slot {
  std::atomic<std::uint32_t> count;
  std::atomic<std::uint32_t> sleepers;
};
static_assert(std::atomic<std::uint32_t>::is_always_lock_free);

MPI_Comm node = MPI_COMM_NULL;
MPI_Win window = MPI_WIN_NULL;
std::vector<Slot*> slots;  // by world rank; null for ranks on other nodes
Slot* mine = nullptr;
bool everyone = false;

long futex(std::atomic<std::uint32_t>* word, int op, std::uint32_t value, const timespec* timeout) {
  return syscall(SYS_futex, reinterpret_cast<std::uint32_t*>(word), op, value, timeout, nullptr, 0);
}

}  // namespace

void open_doorbells() {
  int world_size = 0, world_rank = 0;
  MPI_Comm_size(MPI_COMM_WORLD, &world_size);
  MPI_Comm_rank(MPI_COMM_WORLD, &world_rank);
  if (world_size < 2) return;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, world_rank, MPI_INFO_NULL, &node);
  int node_size = 0;
  MPI_Comm_size(node, &node_size);
  if (node_size < 2) {
    MPI_Comm_free(&node);
    return;
  }
  // The segment is a fresh file mapping, zero-filled; a slot left non-zero would only cost a
  // spurious wake-up (the waiter polls again) or a needless FUTEX_WAKE. Where the MPI cannot
  // share memory this rank goes without (its waits poll; ringing it stays harmless).
  void* base = nullptr;
  MPI_Comm_set_errhandler(node, MPI_ERRORS_RETURN);
  if (MPI_Win_allocate_shared(sizeof(Slot), sizeof(Slot), MPI_INFO_NULL, node, &base, &window) != MPI_SUCCESS) {
    window = MPI_WIN_NULL;
    MPI_Comm_free(&node);
    return;
  }
  MPI_Group world_group, node_group;
  MPI_Comm_group(MPI_COMM_WORLD, &world_group);
  MPI_Comm_group(node, &node_group);
  std::vector<int> local(static_cast<std::size_t>(node_size)), global(local.size());
  for (int i = 0; i < node_size; ++i) local[i] = i;
  MPI_Group_translate_ranks(node_group, node_size, local.data(), world_group, global.data());
  MPI_Group_free(&world_group);
  MPI_Group_free(&node_group);
  slots.assign(static_cast<std::size_t>(world_size), nullptr);
  for (int i = 0; i < node_size; ++i) {
    MPI_Aint size = 0;
    int unit = 0;
    void* at = nullptr;
    MPI_Win_shared_query(window, i, &size, &unit, &at);
    slots[global[i]] = static_cast<Slot*>(at);
  }
  mine = slots[world_rank];
  everyone = node_size == world_size;
}

void close_doorbells() {
  if (window == MPI_WIN_NULL) return;
  mine = nullptr;
  slots.clear();
  everyone = false;
  MPI_Win_free(&window);
  MPI_Comm_free(&node);
}

bool rings(int rank) { return mine && rank >= 0 && rank < static_cast<int>(slots.size()) && slots[rank]; }
bool all_ring() { return mine && everyone; }

void ring(int rank) {
  if (!rings(rank)) return;
  Slot& s = *slots[rank];
  s.count.fetch_add(1);  // sequentially consistent: a sleeper that counted itself is seen below
  if (s.sleepers.load() > 0) futex(&s.count, FUTEX_WAKE, INT_MAX, nullptr);
}

void ring_all() {
  for (int r = 0; r < static_cast<int>(slots.size()); ++r)
    if (slots[r] != mine) ring(r);
}

std::uint32_t bell_count() { return mine ? mine->count.load() : 0; }

void wait_bell(std::uint32_t seen, std::chrono::microseconds timeout) {
  const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(timeout).count();
  const timespec t{static_cast<time_t>(ns / 1000000000), static_cast<long>(ns % 1000000000)};
  mine->sleepers.fetch_add(1);
  futex(&mine->count, FUTEX_WAIT, seen, &t);  // returns at once if the count moved since `seen`
  mine->sleepers.fetch_sub(1);
}

}  // namespace gdp::mpi
