#include "Core/SpscQueue.h"
#include <catch2/catch.hpp>
#include <thread>

using namespace armadillo;
using namespace armadillo::core;

TEST_CASE("SpscQueue: FIFO, bounded, never blocks", "[queue]")
{
    SpscQueue<int, 4> q;
    int out = 0;
    CHECK_FALSE(q.pop(out));
    for (int i = 0; i < 4; ++i) CHECK(q.push(i));
    CHECK_FALSE(q.push(99));   // full: refused, not overwritten
    for (int i = 0; i < 4; ++i) {
        REQUIRE(q.pop(out));
        CHECK(out == i);
    }
    CHECK(q.size() == 0);
}

TEST_CASE("SpscQueue: one producer and one consumer thread keep order", "[queue][threads]")
{
    SpscQueue<long, 256> q;
    constexpr long kCount = 200000;
    std::thread producer([&] {
        for (long i = 0; i < kCount;)
            if (q.push(i)) ++i;
    });
    long expected = 0, value = 0;
    bool inOrder = true;
    while (expected < kCount)
        if (q.pop(value)) inOrder = inOrder && (value == expected++);
    producer.join();
    CHECK(inOrder);
}

TEST_CASE("SeqLock: readers see whole values, never a torn mix", "[queue][threads]")
{
    struct Pair { long a; long b; double c[6]; };
    SeqLock<Pair> box;
    box.store({0, 0, {}});
    std::atomic<bool> done {false};
    std::thread writer([&] {
        for (long i = 1; i < 200000; ++i) box.store({i, -i, {double(i), 0, 0, 0, 0, double(i)}});
        done = true;
    });
    bool whole = true;
    while (!done) {
        const Pair p = box.load();
        whole = whole && p.a == -p.b && p.c[0] == double(p.a) && p.c[5] == double(p.a);
    }
    writer.join();
    CHECK(whole);
    CHECK(box.load().a == 199999);
}

namespace armadillo::core {
/// Holds a write open the way a writer pre-empted in the middle of store() would.
template <typename U>
struct SeqLockProbe {
    static void beginWrite(SeqLock<U>& box) { box.sequence_.fetch_add(1); }
    static void endWrite(SeqLock<U>& box) { box.sequence_.fetch_add(1); }
};
} // namespace armadillo::core

TEST_CASE("SeqLock: a writer stuck mid-write cannot stall a reader; it keeps its last good value", "[queue]")
{
    SeqLock<int> box;
    box.store(7);
    int value = 0;
    REQUIRE(box.tryLoad(value));
    CHECK(value == 7);
    SeqLockProbe<int>::beginWrite(box);   // the writer is pre-empted between its two sequence steps
    int untouched = -1;
    CHECK_FALSE(box.tryLoad(untouched));  // returns after kMaxAttempts instead of spinning
    CHECK(untouched == -1);
    CHECK(box.load(value) == 7);          // the reader's last good value
    SeqLockProbe<int>::endWrite(box);
    box.store(9);
    CHECK(box.load(value) == 9);
    CHECK(box.load() == 9);
}
