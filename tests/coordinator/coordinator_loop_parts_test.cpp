// The parts FleetCoordinator's loop is made of, each on its own: OtherCoordinators,
// StandbyFollower (the takeover rule), OperatorsDesk, PublishSchedule, ReplanRequests, InputQueue,
// and RobotRegistry's gate for robot ids.
#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <thread>

#include "coordinator/coordinator_inputs.hpp"
#include "coordinator/operators_desk.hpp"
#include "coordinator/other_coordinators.hpp"
#include "coordinator/publish_schedule.hpp"
#include "coordinator/replan_requests.hpp"
#include "coordinator/robot_registry.hpp"
#include "coordinator/standby_follower.hpp"
#include "fake_transport.hpp"
#include "fleet_transport/lease_timeouts.hpp"

namespace coordinator {
namespace {

using Clock = std::chrono::steady_clock;
using fleet_transport::CoordinatorRole;
using fleet_transport::CoordinatorStatus;

Clock::duration ms(int milliseconds) { return std::chrono::milliseconds(milliseconds); }

CoordinatorStatus status_of(uint64_t id, uint32_t term, CoordinatorRole role, const std::string& mission = "m1") {
  return {id, term, 1000 + static_cast<int64_t>(id), role, mission, 3};
}

TEST(OtherCoordinators, AStrongerActiveOneCountsOnlyWhileHeard) {
  OtherCoordinators others;
  const Clock::time_point t0 = Clock::now();
  others.heard_status(status_of(7, 2, CoordinatorRole::kActive), t0);
  const CoordinatorStatus mine = status_of(9, 1, CoordinatorRole::kActive);
  ASSERT_NE(others.stronger_active(mine, t0 + ms(500), 1.5), nullptr);
  EXPECT_EQ(others.stronger_active(mine, t0 + ms(500), 1.5)->status.coordinator, 7u);
  EXPECT_EQ(others.stronger_active(mine, t0 + ms(2000), 1.5), nullptr);  // gone
  // A weaker one (lower term) does not count, nor does a standby of a higher term.
  const CoordinatorStatus strong = status_of(9, 3, CoordinatorRole::kActive);
  EXPECT_EQ(others.stronger_active(strong, t0 + ms(100), 1.5), nullptr);
  others.heard_status(status_of(8, 5, CoordinatorRole::kStandby), t0);
  EXPECT_EQ(others.stronger_active(strong, t0 + ms(100), 1.5), nullptr);
}

TEST(OtherCoordinators, TheHighestActiveOfTheMissionIsFollowedAndTermsAreRemembered) {
  OtherCoordinators others;
  const Clock::time_point t0 = Clock::now();
  others.heard_status(status_of(1, 2, CoordinatorRole::kActive), t0);
  others.heard_status(status_of(2, 4, CoordinatorRole::kActive), t0);
  others.heard_status(status_of(3, 9, CoordinatorRole::kActive, "another mission"), t0);
  others.heard_status(status_of(4, 7, CoordinatorRole::kEnded), t0);
  ASSERT_NE(others.highest_active("m1"), nullptr);
  EXPECT_EQ(others.highest_active("m1")->status.coordinator, 2u);
  EXPECT_EQ(others.highest_active("none"), nullptr);
  EXPECT_EQ(others.highest_term(1), 9u);
  EXPECT_EQ(others.highest_term(12), 12u);
  others.forget(3);
  EXPECT_EQ(others.highest_term(1), 7u);
  EXPECT_EQ(others.find(3), nullptr);
  // Progress and mission info are kept beside the heartbeat of the same coordinator.
  fleet_transport::FleetStatus progress;
  progress.coordinator = 2;
  progress.tasks_done = 5;
  others.heard_progress(progress);
  EXPECT_EQ(others.find(2)->progress.tasks_done, 5);
  EXPECT_EQ(others.find(2)->status.term, 4u);
}

// A standby's view: the active coordinator drives robot1 and robot2; the registry says when each
// was last heard here.
struct StandbyScene {
  static constexpr double kLease = 1.0;
  StandbyFollower follower{kLease, 2.0, PublishSchedule::kStatusPeriodS};
  RobotRegistry robots;
  OtherCoordinator active;
  Clock::time_point t0 = Clock::now();

  StandbyScene() {
    active.status = status_of(5, 1, CoordinatorRole::kActive);
    active.progress.assignments = {{"robot1", 0, 0, 2}, {"robot2", 1, 0, 2}};
    active.heard = t0;
    for (const char* id : {"robot1", "robot2"}) heard(id, t0);
    follower.mirror(active, 2, t0);
  }
  void heard(const std::string& id, Clock::time_point when) {
    RobotRecord& robot = robots[id];
    robot.announced = robot.active = robot.has_state = true;
    robot.last_state_received = robot.last_heard = when;
  }
  double takeover_after_s() const { return fleet_transport::LeaseTimeouts{kLease}.standby_takes_over_after_s(); }
};

TEST(StandbyFollower, MirrorsTheRolesOfTheFollowedCoordinator) {
  StandbyScene scene;
  EXPECT_EQ(scene.follower.followed(), 5u);
  ASSERT_EQ(scene.follower.roles().size(), 2u);
  EXPECT_EQ(scene.follower.roles().at("robot2"), 1);
}

TEST(StandbyFollower, NoTakeoverWhileTheActiveOneIsHeard) {
  StandbyScene scene;
  for (int step = 0; step < 100; ++step) {
    const Clock::time_point now = scene.t0 + ms(50 * step);
    scene.active.heard = now;
    scene.heard("robot1", now);
    scene.heard("robot2", now);
    EXPECT_FALSE(scene.follower.should_take_over(scene.active, scene.robots, now)) << "step " << step;
  }
}

TEST(StandbyFollower, TakesOverOnceSilentPastTheLeaseRuleWithEveryRobotHeard) {
  StandbyScene scene;
  const int silent_ms = static_cast<int>(1000 * scene.takeover_after_s());
  bool took_over = false;
  int when_ms = 0;
  for (int t = 0; t <= silent_ms + 2000 && !took_over; t += 50) {
    const Clock::time_point now = scene.t0 + ms(t);
    scene.heard("robot1", now);
    scene.heard("robot2", now);
    took_over = scene.follower.should_take_over(scene.active, scene.robots, now);
    when_ms = t;
  }
  ASSERT_TRUE(took_over);
  EXPECT_GT(when_ms, silent_ms);             // never before the lease rule
  EXPECT_LE(when_ms, silent_ms + 2 * 250 + 100);  // and within two status periods after it
}

TEST(StandbyFollower, NoTakeoverWhileARobotItDrivesIsNotHeardHere) {
  StandbyScene scene;  // a split: robot2 is on the active coordinator's side
  for (int t = 0; t <= 10000; t += 50) {
    const Clock::time_point now = scene.t0 + ms(t);
    scene.heard("robot1", now);
    EXPECT_FALSE(scene.follower.should_take_over(scene.active, scene.robots, now)) << t << " ms";
  }
  // The split heals for the robots but not for the coordinator: robot2 heard again, takeover.
  bool took_over = false;
  for (int t = 10050; t <= 12000 && !took_over; t += 50) {
    const Clock::time_point now = scene.t0 + ms(t);
    scene.heard("robot1", now);
    scene.heard("robot2", now);
    took_over = scene.follower.should_take_over(scene.active, scene.robots, now);
  }
  EXPECT_TRUE(took_over);
}

TEST(StandbyFollower, ARobotThatSaidGoodbyeDoesNotHoldTheTakeoverBack) {
  StandbyScene scene;
  scene.robots["robot2"].said_goodbye = true;
  bool took_over = false;
  for (int t = 0; t <= 6000 && !took_over; t += 50) {
    const Clock::time_point now = scene.t0 + ms(t);
    scene.heard("robot1", now);
    took_over = scene.follower.should_take_over(scene.active, scene.robots, now);
  }
  EXPECT_TRUE(took_over);
}

TEST(StandbyFollower, AnActiveOneHeardAgainAfterASilenceStartsTheCountAfresh) {
  StandbyScene scene;
  const int silent_ms = static_cast<int>(1000 * scene.takeover_after_s());
  // Silent for most of the allowance, robots heard all along...
  for (int t = 0; t < silent_ms - 200; t += 50) {
    scene.heard("robot1", scene.t0 + ms(t));
    scene.heard("robot2", scene.t0 + ms(t));
    ASSERT_FALSE(scene.follower.should_take_over(scene.active, scene.robots, scene.t0 + ms(t)));
  }
  // ...then heard again: a fresh silence must last the whole allowance again.
  const Clock::time_point back = scene.t0 + ms(silent_ms - 200);
  scene.active.heard = back;
  ASSERT_FALSE(scene.follower.should_take_over(scene.active, scene.robots, back));
  for (int t = 50; t < silent_ms; t += 50) {
    const Clock::time_point now = back + ms(t);
    scene.heard("robot1", now);
    scene.heard("robot2", now);
    EXPECT_FALSE(scene.follower.should_take_over(scene.active, scene.robots, now)) << t << " ms after";
  }
}

TEST(OperatorsDesk, EventsAreQueuedUntilPublishedOnce) {
  OperatorsDesk desk(42);
  testing_support::FakeTransport transport;
  desk.report("join", "robot1", "announced");
  desk.report("lost", "robot2", "silent", 2.5);
  EXPECT_TRUE(transport.events.empty());
  desk.publish_events(transport);
  ASSERT_EQ(transport.events.size(), 2u);
  EXPECT_EQ(transport.events[1].coordinator, 42u);
  EXPECT_EQ(transport.events[1].kind, "lost");
  EXPECT_EQ(transport.events[1].value, 2.5);
  desk.publish_events(transport);
  EXPECT_EQ(transport.events.size(), 2u);
}

TEST(OperatorsDesk, AFailingTopicNeverStopsTheCaller) {
  OperatorsDesk desk(1);
  int tries = 0;
  for (int i = 0; i < 3; ++i) {
    EXPECT_NO_THROW(desk.publish("plan", [&] {
      ++tries;
      throw std::runtime_error("access denied by the permissions");
    }));
  }
  EXPECT_EQ(tries, 3);  // each time tried again (the writer may come back), logged once
}

TEST(OperatorsDesk, AnswersAreRememberedForTheLatestRequestsOnly) {
  OperatorsDesk desk(1);
  for (int i = 0; i < 300; ++i) {
    fleet_transport::TaskReply reply;
    reply.request_id = "req-" + std::to_string(i);
    reply.task = i;
    desk.remember(reply);
  }
  EXPECT_EQ(desk.answer_to("req-0"), nullptr);
  EXPECT_EQ(desk.answer_to("req-43"), nullptr);
  ASSERT_NE(desk.answer_to("req-44"), nullptr);
  EXPECT_EQ(desk.answer_to("req-299")->task, 299);
  // The same id again keeps the first answer (a request sent twice is answered alike).
  fleet_transport::TaskReply other;
  other.request_id = "req-299";
  other.task = -7;
  desk.remember(other);
  EXPECT_EQ(desk.answer_to("req-299")->task, 299);
}

TEST(OperatorsDesk, TheMissionIsDueFirstAndAfterEachChange) {
  OperatorsDesk desk(1);
  EXPECT_TRUE(desk.mission_due());
  desk.mission_published();
  EXPECT_FALSE(desk.mission_due());
  desk.mission_changed();
  EXPECT_TRUE(desk.mission_due());
}

TEST(PublishSchedule, HeartbeatEveryPeriodProgressOnChangeButNotTooOften) {
  PublishSchedule schedule;
  const Clock::time_point t0 = Clock::now();
  EXPECT_TRUE(schedule.status_due(t0));
  schedule.status_sent(t0);
  EXPECT_FALSE(schedule.status_due(t0 + ms(240)));
  EXPECT_TRUE(schedule.status_due(t0 + ms(251)));
  schedule.progress_sent(t0);
  EXPECT_FALSE(schedule.progress_due(t0 + ms(10)));
  schedule.progress_changed();
  EXPECT_FALSE(schedule.progress_due(t0 + ms(40)));  // within the gap
  EXPECT_TRUE(schedule.progress_due(t0 + ms(60)));
  schedule.progress_sent(t0 + ms(60));
  EXPECT_FALSE(schedule.progress_due(t0 + ms(500)));  // nothing changed: the period
  EXPECT_TRUE(schedule.progress_due(t0 + ms(561)));
}

TEST(ReplanRequests, LatencyRunsFromTheFirstRequestAndIsTakenOnce) {
  ReplanRequests replans;
  const Clock::time_point t0 = Clock::now();
  EXPECT_FALSE(replans.latency_until(t0));
  replans.ask(t0);
  replans.ask(t0 + ms(100));  // a second reason before the plan: the latency still counts from the first
  EXPECT_TRUE(replans.pending());
  EXPECT_EQ(replans.count(), 2);
  replans.answered();
  EXPECT_FALSE(replans.pending());
  const auto latency = replans.latency_until(t0 + ms(300));
  ASSERT_TRUE(latency);
  EXPECT_NEAR(*latency, 0.3, 1e-9);
  EXPECT_FALSE(replans.latency_until(t0 + ms(400)));
  replans.start_latency(t0 + ms(500));  // a takeover's first plan
  EXPECT_EQ(replans.count(), 2);
  EXPECT_NEAR(*replans.latency_until(t0 + ms(700)), 0.2, 1e-9);
}

TEST(InputQueue, EverythingPushedFromManyThreadsIsTakenOnceInEachThreadsOrder) {
  inputs::InputQueue queue;
  constexpr int kThreads = 4, kEach = 2000;
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&queue, t] {
      for (int i = 0; i < kEach; ++i) queue.push(inputs::Refused{std::to_string(t) + ":" + std::to_string(i)});
    });
  }
  std::vector<int> next(kThreads, 0);
  int taken = 0;
  const auto take = [&] {
    for (const inputs::Input& input : queue.take_all()) {
      const std::string& what = std::get<inputs::Refused>(input).what;
      const int t = std::stoi(what.substr(0, what.find(':')));
      EXPECT_EQ(std::stoi(what.substr(what.find(':') + 1)), next[t]++);
      ++taken;
    }
  };
  while (taken < kThreads * kEach / 2) take();  // taking while they push
  for (std::thread& thread : threads) thread.join();
  take();
  EXPECT_EQ(taken, kThreads * kEach);
  EXPECT_TRUE(queue.take_all().empty());
}

TEST(RobotRegistry, IdsThatBreakTheRuleAreRefusedAndAFloodIsReportedOnlyInPart) {
  RobotRegistry robots;
  int reports = 0;
  const auto count = [&](const std::string&) { ++reports; };
  EXPECT_NE(robots.valid_record("robot_1-a", count), nullptr);
  EXPECT_EQ(robots.valid_record("<script>alert(1)</script>", count), nullptr);
  EXPECT_EQ(robots.valid_record("<script>alert(1)</script>", count), nullptr);  // once per id
  EXPECT_EQ(robots.valid_record("", count), nullptr);
  EXPECT_EQ(robots.valid_record(std::string(33, 'a'), count), nullptr);
  EXPECT_EQ(reports, 3);
  for (int i = 0; i < 1000; ++i) robots.valid_record("bad id " + std::to_string(i), count);
  EXPECT_EQ(reports, 64);  // a flood is refused without a word after the first 64
  EXPECT_EQ(robots.find("<script>alert(1)</script>"), nullptr);  // never a record
}

}  // namespace
}  // namespace coordinator
