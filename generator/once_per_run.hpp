// Results computed once per run of the generator and shared by emit's
// worker threads: the first thread to ask for a key computes, the others
// wait for its result (or its exception). Kept for the whole run (the
// default catalogue's Taylor pieces, edge and zero series: tens of MB), and
// never destroyed: freeing them number by number at exit was half of what
// `emit` did on one core after its workers (~20 ms); the process's end
// returns them at once.
#pragma once

#include <cstdint>
#include <exception>
#include <future>
#include <map>
#include <mutex>

namespace mollify::gen {

template <class T, class Compute>
const T& once_per_run(std::uint64_t key, Compute compute) {
    static std::mutex mutex;
    static auto& all = *new std::map<std::uint64_t, std::shared_future<T>>;
    std::promise<T> promise;
    std::shared_future<T> future;
    bool mine = false;
    {
        const std::lock_guard<std::mutex> lock(mutex);
        auto [it, fresh] = all.try_emplace(key);
        if (fresh) it->second = promise.get_future().share();
        future = it->second;
        mine = fresh;
    }
    if (mine) {
        try {
            promise.set_value(compute());
        } catch (...) {
            promise.set_exception(std::current_exception());
        }
    }
    return future.get();
}

}  // namespace mollify::gen
