//! Sensor.
