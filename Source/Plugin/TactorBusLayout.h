#pragma once
// The VST3 Tactors bus's layouts (issue 33, docs/PLUGIN.md "Tactors bus"). VST3 knows speaker
// arrangements, not "nine discrete channels", and JUCE 7.0.5's VST3 code does not carry discrete
// channel sets across the plugin boundary intact (discrete channel 0 comes back as "centre", the
// others as stray speaker bits), so the bus is declared as the two arrangements of the right size
// that JUCE converts exactly both ways: 7.0.2 for 9 tactors and 7.1.4 for 12. Tactor channel k is
// the bus's k-th channel as the VST3 numbers it — the order a DAW shows and routes — which is
// not JUCE's own order of the same speakers, hence the tables (the VST3 order of each layout, as
// JUCE 7.0.5's juce_VST3Common.h lists it for k70_2 and k71_4). Header only: the plugin and its
// hosted tests read the same tables.
#include <juce_audio_basics/juce_audio_basics.h>
#include <array>

namespace armadillo::plugin::tactorbus {

using T = juce::AudioChannelSet;
inline constexpr std::array<T::ChannelType, 9> kOrder9 {T::left, T::right, T::centre, T::leftSurroundRear, T::rightSurroundRear,
                                                        T::leftSurroundSide, T::rightSurroundSide, T::topSideLeft, T::topSideRight};
inline constexpr std::array<T::ChannelType, 12> kOrder12 {T::left, T::right, T::centre, T::LFE, T::leftSurroundRear, T::rightSurroundRear,
                                                          T::leftSurroundSide, T::rightSurroundSide, T::topFrontLeft, T::topFrontRight,
                                                          T::topRearLeft, T::topRearRight};

/// The bus's layout for 9 or 12 tactors.
inline juce::AudioChannelSet layoutFor(int tactors)
{
    return tactors == 12 ? juce::AudioChannelSet::create7point1point4() : juce::AudioChannelSet::create7point0point2();
}

/// Whether `set` is one of the bus's layouts.
inline bool isTactorLayout(const juce::AudioChannelSet& set)
{
    return set == layoutFor(9) || set == layoutFor(12);
}

/// The index within `set` (JUCE's order) of tactor channel k (0-based, the VST3's order); −1
/// when `set` is not a Tactors layout or k is out of range.
inline int juceIndexOfTactor(const juce::AudioChannelSet& set, int k)
{
    if (set == layoutFor(9) && k >= 0 && k < 9) return set.getChannelIndexForType(kOrder9[static_cast<std::size_t>(k)]);
    if (set == layoutFor(12) && k >= 0 && k < 12) return set.getChannelIndexForType(kOrder12[static_cast<std::size_t>(k)]);
    return -1;
}

} // namespace armadillo::plugin::tactorbus
