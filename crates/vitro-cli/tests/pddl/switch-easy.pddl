(define (problem easy) (:domain switch)
  (:init (off))
  (:goal (and (on))))
