; A light that can only be switched on.
(define (domain switch)
  (:requirements :strips)
  (:predicates (off) (on) (broken))
  (:action switch-on :parameters () :precondition (and (off)) :effect (and (on) (not (off)))))
