// The Standard MIDI File writer, read back by a reader written here from the SMF 1.0
// specification (chunks, big-endian header, variable-length delta times, meta events).
#include "Mapping/MidiFile.h"
#include "Mapping/SmfReader.h"
#include <catch2/catch.hpp>
#include <cstdio>
#include <fstream>
#include <iterator>

using namespace armadillo::mapping;
using namespace armadillo::mapping::test;

TEST_CASE("The SMF is format 1 with a tempo track, and event times are within 1 ms", "[mapping][smf]")
{
    MidiFileWriter w(10.0);
    const double times[] {10.0, 10.0031, 10.5, 11.23456, 10.2};   // out of order on purpose (a note-off due earlier)
    std::uint8_t k = 0;
    for (double t : times) {
        MidiEvent e;
        e.t = t;
        e.size = 3;
        e.bytes = {0xB0, 1, k++};
        w.add(e);
    }
    MidiEvent pc;
    pc.t = 12.0;
    pc.size = 2;
    pc.bytes = {0xC3, 5, 0};
    w.add(pc);
    const std::vector<std::uint8_t> bytes = w.bytes();
    const Smf smf = readSmf(bytes);
    CHECK(smf.format == 1);
    CHECK(smf.tracks == 2);
    CHECK(smf.division == 960);
    CHECK(smf.tempo == 500000);
    REQUIRE(smf.events.size() == 6);
    const double want[] {0.0, 0.0031, 0.2, 0.5, 1.23456, 2.0};
    const int values[] {0, 1, 4, 2, 3};
    for (std::size_t i = 0; i < 6; ++i) CHECK(std::fabs(smf.events[i].seconds - want[i]) < 0.001);
    for (std::size_t i = 0; i < 5; ++i) CHECK(smf.events[i].bytes[2] == values[i]);
    CHECK(smf.events[5].bytes.size() == 2);
    CHECK(smf.events[5].bytes[0] == 0xC3);

    const std::string path = std::string(ARMADILLO_BINARY_DIR) + "/test-mapping.mid";
    w.write(path);
    std::ifstream in(path, std::ios::binary);
    const std::vector<std::uint8_t> back((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    CHECK(back == bytes);
    std::remove(path.c_str());
}

TEST_CASE("Long gaps use multi-byte delta times", "[mapping][smf]")
{
    MidiFileWriter w;
    MidiEvent e;
    e.size = 3;
    e.bytes = {0x90, 60, 100};
    e.t = 0.0;
    w.add(e);
    e.t = 3600.0;   // an hour later: 6 912 000 ticks, a 4-byte quantity
    w.add(e);
    const Smf smf = readSmf(w.bytes());
    REQUIRE(smf.events.size() == 2);
    CHECK(smf.events[1].seconds == Approx(3600.0).margin(0.001));
}
