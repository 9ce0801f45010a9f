"""Peripheral models of the STM32F411 (RM0383), only what the firmware uses."""
