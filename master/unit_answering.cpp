#include "master/unit_answering.hpp"

namespace unima::master {

UnitAnswering::Transition UnitAnswering::answered() {
  failures_in_a_row_ = 0;
  first_failure_.reset();
  if (!silent_since_) return Transition::none;
  silent_since_.reset();
  return Transition::answers_again;
}

UnitAnswering::Transition UnitAnswering::failed(Time sent) {
  if (failures_in_a_row_++ == 0) first_failure_ = sent;
  if (silent_since_ || failures_in_a_row_ < failures_to_silent) return Transition::none;
  silent_since_ = first_failure_;
  return Transition::stopped_answering;
}

}  // namespace unima::master
