// ScratchPool (sim/core/scratch_pool.h): a lease reuses a returned object, the pool makes only
// as many objects as were lent at once, and objects come back however many threads borrow them.
#include "sim/core/scratch_pool.h"

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <vector>

using namespace fovsim;

TEST(ScratchPool, ALeaseReusesWhatTheLastOneReturned) {
  ScratchPool<std::vector<float>> pool;
  const std::vector<float>* first = nullptr;
  {
    auto a = pool.take();
    a->assign(100, 1.f);
    first = a.get();
  }
  auto b = pool.take();
  EXPECT_EQ(b.get(), first);  // the same object, with what the last user left in it
  ASSERT_EQ(b->size(), 100u);
  EXPECT_EQ((*b)[0], 1.f);
  auto c = pool.take();  // b is still lent: a new one
  EXPECT_NE(c.get(), first);
  EXPECT_EQ(pool.made(), 2u);
}

TEST(ScratchPool, MakesAsManyAsWereLentAtOnce) {
  ScratchPool<std::vector<float>> pool;
  {
    std::vector<ScratchPool<std::vector<float>>::Lease> held;
    for (int i = 0; i < 3; ++i) held.push_back(pool.take());
  }
  for (int i = 0; i < 10; ++i) (void)pool.take();  // one at a time: the three are reused
  EXPECT_EQ(pool.made(), 3u);
  pool.clear();
  EXPECT_EQ(pool.made(), 0u);
  // From two threads, 1000 leases: never more objects than leases alive at once (<= 2 here,
  // the arena's threads, each holding one lease at a time).
  tbb::task_arena arena(2);
  std::atomic<int> uses{0};
  arena.execute([&] {
    tbb::parallel_for(0, 1000, [&](int) {
      auto l = pool.take();
      l->push_back(1.f);
      ++uses;
    });
  });
  EXPECT_EQ(uses.load(), 1000);
  EXPECT_GE(pool.made(), 1u);
  EXPECT_LE(pool.made(), 2u);
}
