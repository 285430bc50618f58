// MIDI out through the ALSA sequencer: each channel message becomes the sequencer event the ALSA
// API defines for it (alsa/seq_event.h: type, channel, note/param/value; pitch bend signed around
// 0), sent directly to subscribers; opening without a sequencer is an IoError that names why.
#include "Audio/SequencerOut.h"
#include "Core/Errors.h"
#include <alsa/asoundlib.h>
#include <catch2/catch.hpp>
#include <filesystem>

using namespace armadillo;
using namespace armadillo::core;

TEST_CASE("Channel messages become the ALSA sequencer events of the same meaning", "[audio][midi]")
{
    snd_seq_event_t ev;
    const std::uint8_t on[] {0x92, 60, 100};
    REQUIRE(audio::encodeSequencerEvent(on, 3, 5, &ev));
    CHECK(ev.type == SND_SEQ_EVENT_NOTEON);
    CHECK(ev.data.note.channel == 2);
    CHECK(ev.data.note.note == 60);
    CHECK(ev.data.note.velocity == 100);
    CHECK(ev.source.port == 5);
    CHECK(ev.dest.client == SND_SEQ_ADDRESS_SUBSCRIBERS);
    CHECK(ev.queue == SND_SEQ_QUEUE_DIRECT);

    const std::uint8_t off[] {0x80, 61, 0};
    REQUIRE(audio::encodeSequencerEvent(off, 3, 0, &ev));
    CHECK(ev.type == SND_SEQ_EVENT_NOTEOFF);
    CHECK(ev.data.note.note == 61);

    const std::uint8_t cc[] {0xBF, 74, 12};
    REQUIRE(audio::encodeSequencerEvent(cc, 3, 0, &ev));
    CHECK(ev.type == SND_SEQ_EVENT_CONTROLLER);
    CHECK(ev.data.control.channel == 15);
    CHECK(ev.data.control.param == 74);
    CHECK(ev.data.control.value == 12);

    const std::uint8_t bend[] {0xE0, 0x00, 0x40};   // 8192: the centre
    REQUIRE(audio::encodeSequencerEvent(bend, 3, 0, &ev));
    CHECK(ev.type == SND_SEQ_EVENT_PITCHBEND);
    CHECK(ev.data.control.value == 0);
    const std::uint8_t bendTop[] {0xE0, 0x7F, 0x7F};   // 16383
    REQUIRE(audio::encodeSequencerEvent(bendTop, 3, 0, &ev));
    CHECK(ev.data.control.value == 8191);

    const std::uint8_t program[] {0xC1, 5};
    REQUIRE(audio::encodeSequencerEvent(program, 2, 0, &ev));
    CHECK(ev.type == SND_SEQ_EVENT_PGMCHANGE);
    CHECK(ev.data.control.value == 5);
    const std::uint8_t pressure[] {0xD3, 90};
    REQUIRE(audio::encodeSequencerEvent(pressure, 2, 0, &ev));
    CHECK(ev.type == SND_SEQ_EVENT_CHANPRESS);
    CHECK(ev.data.control.value == 90);

    const std::uint8_t sysex[] {0xF0, 1, 0xF7};
    CHECK_FALSE(audio::encodeSequencerEvent(sysex, 3, 0, &ev));
    CHECK_FALSE(audio::encodeSequencerEvent(on, 2, 0, &ev));   // a note needs 3 bytes
}

TEST_CASE("A sequencer port opens where /dev/snd/seq exists; elsewhere the error says why", "[audio][midi]")
{
    if (std::filesystem::exists("/dev/snd/seq")) {
        audio::SequencerOut out("ARMadillo test");
        CHECK(out.port() >= 0);
        const std::uint8_t cc[] {0xB0, 1, 2};
        CHECK(out.send(cc, 3));
    } else {
        CHECK_THROWS_AS(audio::SequencerOut("ARMadillo test"), IoError);
        CHECK_THROWS_WITH(audio::SequencerOut("ARMadillo test"), Catch::Contains("/dev/snd/seq") && Catch::Contains("ARMadillo test"));
    }
}
