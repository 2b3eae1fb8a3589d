#pragma once
// The scenes a service holds: one session per loaded scene, and the names being loaded, under one
// lock. A load reserves its name first, so two concurrent loads never both open a scene's store.

#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "ispars/service/roadmap_session.hpp"

namespace ispars::service {

/// The loaded scenes' sessions by name, and the names reserved by loads under way. Safe to call
/// from many threads; it never calls into a session while its lock is held.
class SceneRegistry {
 public:
  /// A name reserved for a load: released when this goes, unless the load added its session.
  class Reservation {
   public:
    Reservation(const Reservation&) = delete;
    Reservation& operator=(const Reservation&) = delete;
    ~Reservation();
    /// The load succeeded: `session` is the scene's from now on, and the name is no longer reserved.
    void add(std::shared_ptr<RoadmapSession> session);

   private:
    friend class SceneRegistry;
    Reservation(SceneRegistry& registry, std::string name) : registry_(registry), name_(std::move(name)) {}
    SceneRegistry& registry_;
    const std::string name_;
    bool added_ = false;
  };

  /// Reserves `name` for a load. Throws InputError (file "request", field scene) when the scene
  /// is loaded or being loaded.
  [[nodiscard]] std::unique_ptr<Reservation> reserve(const std::string& name);
  /// The session of `name`; nullptr when it is not loaded.
  [[nodiscard]] std::shared_ptr<RoadmapSession> find(const std::string& name) const;
  /// The loaded scenes' sessions, by name.
  [[nodiscard]] std::vector<std::shared_ptr<RoadmapSession>> sessions() const;
  /// The loaded scenes' names, in order.
  [[nodiscard]] std::vector<std::string> names() const;
  /// The names loaded or being loaded: the stores a background reader must leave alone.
  [[nodiscard]] std::vector<std::string> held_or_loading() const;
  /// Forgets the session of `name` (its holders keep it as long as they hold it).
  void erase(const std::string& name);

 private:
  mutable std::mutex mutex_;
  std::map<std::string, std::shared_ptr<RoadmapSession>> sessions_;
  std::set<std::string> loading_;
};

}  // namespace ispars::service
