from hypothesis import HealthCheck, settings

# Every property test is seeded: hypothesis draws the same examples on every run.
settings.register_profile(
    "polyell",
    derandomize=True,
    deadline=None,
    max_examples=40,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.load_profile("polyell")
