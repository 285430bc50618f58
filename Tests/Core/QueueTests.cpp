#include "Core/SpscQueue.h"
#include <catch2/catch.hpp>
#include <thread>

using namespace armadillo;

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
