#pragma once
// The core's own headless OpenGL 4.5 core context.
//
// Why a dedicated thread: the host (Blender's viewport, or `blender -b`) may
// have its own GL/GLX/EGL context current on the calling thread, and libglvnd
// refuses to switch a thread between window-system APIs. All GL work of the
// core therefore runs on one worker thread that owns the EGL context; the
// caller's thread and whatever context it had current are never touched.
#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

namespace pointnpr::gl {

struct DeviceInfo {
  std::string vendor;
  std::string renderer;
  std::string version;
  std::string egl_platform;   // "device" or "surfaceless"
  bool software = false;      // llvmpipe / softpipe
  bool int64_atomics = false; // 64-bit SSBO atomicMin available
  int max_texture_size = 0;
};

// POINTNPR_EGL_DEVICE: unset or "auto" (a GPU when EGL enumerates one,
// else Mesa's llvmpipe) or "software" (llvmpipe only); any other value
// throws GLError listing the accepted ones.
bool software_device_forced();
// The error when no EGL display opens: what was tried, what to install.
std::string no_display_message(const std::vector<std::string>& failures, bool software_forced);

class Device {
 public:
  // The process-wide device; created on first use. Throws GLError with the
  // reason and what to install when no context can be made.
  static Device& instance();
  // Stops the GL thread and releases the context (idempotent).
  static void shutdown();
  // Whether the device currently exists (without creating it).
  static bool exists();

  ~Device();
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  const DeviceInfo& info() const { return info_; }

  // Runs `fn` on the GL thread and returns its result; exceptions thrown
  // there are rethrown here. Calls from the GL thread itself run inline.
  template <class Fn>
  auto run(Fn&& fn) -> std::invoke_result_t<Fn> {
    using R = std::invoke_result_t<Fn>;
    if (std::this_thread::get_id() == thread_.get_id()) return fn();
    std::packaged_task<R()> task(std::forward<Fn>(fn));
    auto future = task.get_future();
    post([&task] { task(); });
    return future.get();
  }

 private:
  Device();
  void post(std::function<void()> job);
  void thread_main(std::promise<void> ready);

  DeviceInfo info_;
  std::thread thread_;
  std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<std::function<void()>> jobs_;
  bool stopping_ = false;
  // EGL handles, owned by the GL thread.
  void* display_ = nullptr;
  void* context_ = nullptr;
};

// Throws GLError naming `what` when GL reports an error (call on GL thread).
void check_gl(const char* what);

}  // namespace pointnpr::gl
