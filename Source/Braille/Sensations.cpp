#include "Braille/Sensations.h"
#include <bit>

namespace armadillo::braille {

MotorSet rowSensation(Dots cell, int row) noexcept
{
    if (row < 0 || row > 2) return 0;
    const bool left = (cell & dot(row + 1)) != 0;    // dots 1, 2, 3
    const bool right = (cell & dot(row + 4)) != 0;   // dots 4, 5, 6
    MotorSet set = 0;
    if (left) set |= motorBit(row, 0);
    if (right) set |= motorBit(row, 2);
    if (left && right) set |= motorBit(row, 1);      // the parity serif
    return set;
}

const char* displayMethodName(DisplayMethod m) noexcept
{
    switch (m) {
    case DisplayMethod::Rows: return "rows";
    case DisplayMethod::WholeCharacter: return "whole";
    case DisplayMethod::ColumnPairs: return "columns";
    case DisplayMethod::DotByDot: return "dots";
    }
    return "rows";
}

bool parseDisplayMethod(const std::string& name, DisplayMethod& out) noexcept
{
    for (int i = 0; i < kDisplayMethodCount; ++i) {
        const auto m = static_cast<DisplayMethod>(i);
        if (name == displayMethodName(m)) {
            out = m;
            return true;
        }
    }
    return false;
}

namespace {
MotorSet columnSet(Dots cell, int firstDot, int motorColumn)
{
    MotorSet set = 0;
    for (int r = 0; r < 3; ++r)
        if (cell & dot(firstDot + r)) set |= motorBit(r, motorColumn);
    return set;
}
} // namespace

std::vector<MotorSet> cellSteps(Dots cell, DisplayMethod method)
{
    switch (method) {
    case DisplayMethod::Rows:
        return {rowSensation(cell, 0), rowSensation(cell, 1), rowSensation(cell, 2)};
    case DisplayMethod::WholeCharacter:
        return {static_cast<MotorSet>(columnSet(cell, 1, 0) | columnSet(cell, 4, 2))};
    case DisplayMethod::ColumnPairs:
        return {columnSet(cell, 1, 0), columnSet(cell, 4, 2)};
    case DisplayMethod::DotByDot: {
        std::vector<MotorSet> steps;
        for (int d = 1; d <= 6; ++d)
            if (cell & dot(d)) steps.push_back(motorBit((d - 1) % 3, d <= 3 ? 0 : 2));
        if (steps.empty()) steps.push_back(0);
        return steps;
    }
    }
    return {};
}

std::string motorList(MotorSet set)
{
    std::string s;
    for (int i = 0; i < core::kMaxMotors; ++i)
        if (set & (1u << i)) {
            if (!s.empty()) s += ',';
            s += std::to_string(i + 1);
        }
    return s.empty() ? "-" : s;
}

int hammingDistance(MotorSet a, MotorSet b) noexcept
{
    return std::popcount(static_cast<unsigned>(a ^ b));
}

} // namespace armadillo::braille
