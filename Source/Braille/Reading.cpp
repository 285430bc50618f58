#include "Braille/Reading.h"

namespace armadillo::braille {

std::vector<ReadingUnit> layoutDocument(const BrailleDocument& doc, DisplayMethod method)
{
    std::vector<ReadingUnit> units;
    for (std::size_t m = 0; m < doc.messages.size(); ++m) {
        if (m > 0) units.push_back({UnitKind::MessageGap, 0, static_cast<int>(m), 0, {0}});
        const auto& symbols = doc.messages[m].symbols;
        for (std::size_t s = 0; s < symbols.size(); ++s) {
            if (symbols[s].isSpace()) {
                if (!units.empty() && units.back().kind == UnitKind::Cell)
                    units.push_back({UnitKind::WordGap, 0, static_cast<int>(m), static_cast<int>(s), {0}});
                continue;
            }
            for (Dots c : symbols[s].cells)
                units.push_back({UnitKind::Cell, c, static_cast<int>(m), static_cast<int>(s), cellSteps(c, method)});
        }
        while (!units.empty() && units.back().kind == UnitKind::WordGap) units.pop_back();
    }
    return units;
}

void ReadingCursor::rewind() noexcept
{
    unit_ = -1;
    step_ = 0;
    forward_ = true;
    restartUnit_ = false;
}

ReadingStep ReadingCursor::stepAt() const
{
    ReadingStep s;
    const auto& u = units_[static_cast<std::size_t>(unit_)];
    s.unit = unit_;
    s.step = step_;
    s.firstOfUnit = step_ == 0;
    switch (u.kind) {
    case UnitKind::Cell:
        s.kind = StepKind::Cell;
        s.motors = u.steps[static_cast<std::size_t>(step_)];
        break;
    case UnitKind::WordGap: s.kind = StepKind::WordGap; break;
    case UnitKind::MessageGap: s.kind = StepKind::MessageGap; break;
    }
    return s;
}

ReadingStep ReadingCursor::advance(bool forward)
{
    const int n = static_cast<int>(units_.size());
    if (forward != forward_) {
        forward_ = forward;
        restartUnit_ = unit_ >= 0 && unit_ < n;
    }
    if (restartUnit_) {
        restartUnit_ = false;
        step_ = 0;
        return stepAt();
    }
    const bool inside = unit_ >= 0 && unit_ < n;
    if (inside && step_ + 1 < static_cast<int>(units_[static_cast<std::size_t>(unit_)].steps.size())) {
        ++step_;
        return stepAt();
    }
    // Next unit in reading order; from outside the text, the first unit on that side.
    int next = 0;
    if (forward) next = unit_ < 0 ? 0 : unit_ + 1;
    else next = unit_ >= n ? n - 1 : unit_ - 1;
    if (next < 0 || next >= n) {
        unit_ = forward ? n : -1;
        step_ = 0;
        return {};   // TextEnd
    }
    unit_ = next;
    step_ = 0;
    return stepAt();
}

} // namespace armadillo::braille
