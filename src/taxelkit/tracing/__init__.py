"""Fine-edge tracing of paper 000: edge direction, error vector, controller."""
