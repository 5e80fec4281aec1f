"""The pass/fail reporting shared by the training scripts' self-tests (smoke and fidelity tests run by CTest)."""


class Checks:
    def __init__(self):
        self.failures = []

    def __call__(self, condition, message):
        print(("ok   " if condition else "FAIL ") + message)
        if not condition:
            self.failures.append(message)

    def summary(self, name):
        """Prints the verdict; returns the process exit status."""
        print(f"{name}: " + ("all checks passed" if not self.failures else "FAILED: " + "; ".join(self.failures)))
        return 1 if self.failures else 0
