; Nothing makes the light broken: no plan exists.
(define (problem never) (:domain switch)
  (:init (off))
  (:goal (and (on) (broken))))
