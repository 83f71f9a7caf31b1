// The method memo in the frame engine (method_memo.h; docs/architecture.md "Data flow of one
// frame": method memo): per method entry its state (replayed from an earlier run's sequence,
// or recorded for the next one), and the group-level step that opens the memo and gives every
// entry its key. Cell::replay_method, Cell::record_frame and Cell::memo_images (cell_memo.cpp)
// are the per-frame steps.
#pragma once
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sim/experiment/method_memo.h"

namespace fovsim {

struct Cell;
struct Shared;
class ReferenceCache;

// One method entry's memo: `replay` holds its whole sequence when an earlier run computed it
// (the method is not run, its rows are built from it); else, with the memo on, `rec` collects
// the sequence, stored under `key` when the cell completes.
struct MethodMemoState {
  std::optional<MemoEntry> replay;
  size_t replay_next = 0;
  std::unique_ptr<MemoEntry> rec;
  std::string key;
};

// The frames of a run without --target in evaluation order (frame_order.h): (trace frame,
// recorded), the warm-up frames first.
std::vector<std::pair<int, bool>> memo_frame_list(const Shared& sh);

// The method memo with the reference cache, except under --target (`sampled`): each method
// entry found in it is replayed, every other one recorded; each cell's manifest lists the
// replayed ones (`memoised_methods`). nullptr without the cache or under --target.
std::unique_ptr<MethodMemo> open_method_memo(const Shared& sh, const ReferenceCache* rc,
                                             std::vector<std::unique_ptr<Cell>>& cells,
                                             bool sampled);

}  // namespace fovsim
