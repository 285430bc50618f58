#pragma once
// A scene's parameters as lock-free atomics: setParameter() may come from any thread (host
// automation, UI, CLI), the control and audio threads read the latest value without locks.
#include "Core/Scene.h"
#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <string_view>
#include <vector>

namespace armadillo::instruments {

class ParameterSet {
public:
    explicit ParameterSet(std::vector<core::ParamSpec> specs)
        : specs_(std::move(specs)), values_(std::make_unique<std::atomic<float>[]>(specs_.size()))
    {
        static_assert(std::atomic<float>::is_always_lock_free, "parameters must cross threads without locks");
        for (std::size_t i = 0; i < specs_.size(); ++i) values_[i].store(specs_[i].defaultValue, std::memory_order_relaxed);
    }

    const std::vector<core::ParamSpec>& specs() const noexcept { return specs_; }
    int size() const noexcept { return static_cast<int>(specs_.size()); }

    /// Clamps to the spec's range; NaN is ignored (a parameter never becomes NaN).
    void set(int index, float value) noexcept
    {
        if (index < 0 || index >= size() || std::isnan(value)) return;
        const core::ParamSpec& s = specs_[static_cast<std::size_t>(index)];
        float v = std::clamp(value, s.min, s.max);
        if (!s.choices.empty()) v = std::round(v);
        values_[static_cast<std::size_t>(index)].store(v, std::memory_order_relaxed);
    }
    /// The value as double (the DSP computes in double; float storage keeps the atomic lock-free).
    double get(int index) const noexcept { return static_cast<double>(values_[static_cast<std::size_t>(index)].load(std::memory_order_relaxed)); }

    /// Index of a stable id, or −1. Not real-time (string compares); tests and hosts use it.
    int indexOf(std::string_view id) const noexcept
    {
        for (std::size_t i = 0; i < specs_.size(); ++i)
            if (specs_[i].id == id) return static_cast<int>(i);
        return -1;
    }

private:
    std::vector<core::ParamSpec> specs_;
    std::unique_ptr<std::atomic<float>[]> values_;
};

/// Index of a parameter id in any scene's parameters(), or −1 (not real-time).
inline int parameterIndex(const core::Scene& scene, std::string_view id)
{
    const auto specs = scene.parameters();
    for (std::size_t i = 0; i < specs.size(); ++i)
        if (specs[i].id == id) return static_cast<int>(i);
    return -1;
}

} // namespace armadillo::instruments
