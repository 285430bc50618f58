#pragma once
// Reads Arm Braille back from motor frames the way a reader of the rows method does
// (docs/BRAILLE.md): the "next" sweep (underside motors 2, 5, 8 one after another) opens a name,
// each step lights one motor row (left dot = column 0, right dot = column 2, both = the whole
// row), a step on the wrist row starts a new letter, the underside line once is a word gap and
// twice ("your turn") closes the name. The letters come from the braille alphabet's definition
// (dots per letter), not from the code under test.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace armadillo::test {

struct MotorFrame {
    double t = 0.0;
    std::uint16_t mask = 0;   ///< bit i = motor index i on (level > 0)
};

inline char brailleLetter(int dots)
{
    // Grade 1 letters: dot d ⇒ bit d−1 (1 = top left … 6 = bottom right).
    static const std::map<int, char> table = [] {
        const char* cells[26] = {"1", "12", "14", "145", "15", "124", "1245", "125", "24", "245", "13", "123", "134",
                                 "1345", "135", "1234", "12345", "1235", "234", "2345", "136", "1236", "2456", "1346", "13456", "1356"};
        std::map<int, char> m;
        for (int i = 0; i < 26; ++i) {
            int bits = 0;
            for (const char* c = cells[i]; *c; ++c) bits |= 1 << (*c - '1');
            m[bits] = static_cast<char>('a' + i);
        }
        return m;
    }();
    const auto it = table.find(dots);
    return it == table.end() ? '?' : it->second;
}

/// Every name shown in the frames, in order.
inline std::vector<std::string> decodeNames(const std::vector<MotorFrame>& frames)
{
    struct Step { std::uint16_t mask; double t0, t1; };
    std::vector<Step> steps;
    for (std::size_t i = 0; i < frames.size();) {
        std::size_t j = i;
        while (j < frames.size() && frames[j].mask == frames[i].mask) ++j;
        const double t1 = j < frames.size() ? frames[j].t : frames.back().t;
        if (frames[i].mask != 0 && t1 - frames[i].t >= 0.03) steps.push_back({frames[i].mask, frames[i].t, t1});
        i = j;
    }
    constexpr std::uint16_t b1 = 1u << 1, b4 = 1u << 4, b7 = 1u << 7, under = b1 | b4 | b7;
    std::vector<std::string> names;
    for (std::size_t i = 0; i + 2 < steps.size(); ++i) {
        if (!(steps[i].mask == b1 && steps[i + 1].mask == b4 && steps[i + 2].mask == b7)) continue;
        std::string name;
        int cell = -1;
        bool closed = false;
        std::size_t k = i + 3;
        for (; k < steps.size(); ++k) {
            const Step& s = steps[k];
            if (s.mask == under) {
                if (cell >= 0) name += brailleLetter(cell), cell = -1;
                if (k + 1 < steps.size() && steps[k + 1].mask == under && steps[k + 1].t0 - s.t1 < 0.3) {
                    closed = true;
                    break;
                }
                name += ' ';
                continue;
            }
            int row = -1, dots = 0;
            for (int r = 0; r < 3; ++r) {
                const std::uint16_t left = 1u << (3 * r), mid = 1u << (3 * r + 1), right = 1u << (3 * r + 2);
                if (s.mask == left) row = r, dots = 1 << r;
                else if (s.mask == right) row = r, dots = 1 << (r + 3);
                else if (s.mask == (left | mid | right)) row = r, dots = (1 << r) | (1 << (r + 3));
            }
            if (row < 0) break;   // not a braille row: the name was interrupted
            if (row == 0 && cell >= 0) name += brailleLetter(cell), cell = -1;
            cell = cell < 0 ? dots : cell | dots;
        }
        if (closed) names.push_back(name);
        i = k;
    }
    return names;
}

} // namespace armadillo::test
